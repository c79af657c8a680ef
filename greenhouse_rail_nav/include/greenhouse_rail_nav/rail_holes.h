#pragma once

#include <Eigen/Geometry>

#include "greenhouse_rail_nav/cloud_projection.h"
#include "greenhouse_rail_nav/depth_camera.h"

namespace greenhouse_rail_nav {

/// Shiny pipes seen as what an active-stereo camera does not see: the projected pattern reflects away from polished
/// round steel, and the pipes come out as long strips without depth on a floor with depth. Returns a cloud of the
/// same layout in which each pixel without depth gets the point where its ray (from `projection`) meets the
/// horizontal plane `height_m` above base_link's floor, moved back to the camera frame, and every other pixel none.
/// Columns mostly without depth (the invalid band at the image's left, a wall of glare) give nothing: the share of
/// a column without depth must stay below one half. The detector runs its search on this cloud when the depth
/// points themselves show no rails.
OrganisedCloud holesOnPlane(const OrganisedCloud& cloud, const CloudProjection& projection,
                            const Eigen::Isometry3d& camera_in_base, double height_m);

}  // namespace greenhouse_rail_nav
