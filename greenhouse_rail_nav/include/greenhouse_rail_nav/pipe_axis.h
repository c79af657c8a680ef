#pragma once

#include <vector>

#include <Eigen/Core>

#include "greenhouse_rail_nav/rail_pair.h"

namespace greenhouse_rail_nav {

/// The axis of a pipe rail of radius pipe_radius_m [m] from the line through its visible points: the camera sees the
/// side of the pipe that faces it, nearer the camera than the axis. A circle of the pipe's radius is fitted across
/// the rail (lateral offset, height) to the band points before thinning (raw_band, base_link) near the line; when
/// too few points are there or the fit fails, the mean offset of a visible half-cylinder is used. camera_xyz: the
/// camera in base_link [m]. pipe_radius_m <= 0: the rail unchanged. Only the line's centroid moves sideways.
RailLine pipeAxisLine(const RailLine& rail, const Eigen::Vector3d& camera_xyz,
                      const std::vector<Eigen::Vector3f>& raw_band, double pipe_radius_m);

}  // namespace greenhouse_rail_nav
