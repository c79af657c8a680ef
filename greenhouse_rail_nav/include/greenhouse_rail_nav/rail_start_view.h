#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "greenhouse_rail_nav/cloud_projection.h"
#include "greenhouse_rail_nav/rail_detector_params.h"
#include "greenhouse_rail_nav/rail_pair.h"

namespace greenhouse_rail_nav {

/// Side of the floor cells that RailDetector::cropToRailBand marks where it saw the floor [m].
constexpr double kFloorBinM = 0.05;

/// Whether the floor cell that holds q (x, y in base_link [m]) is marked in floor_cells, the grid of
/// RailDetector::cropToRailBand for these parameters; false outside the grid.
bool floorSeen(const std::vector<float>& floor_cells, const Eigen::Vector2d& q, const RailDetectorParams& p);

/// Whether the rails' start was in the camera's view, and if not, why.
struct RailStartView {
  bool seen = true;
  std::string why;  ///< empty when seen
};

/// The rail detector's start stage. For each rail (base_link):
/// 1. the point start_view_margin_m before its start must lie inside the image (image_margin_px): where the rails are
///    cut by the image border, the floor beside the cut may still be seen, but the start is not;
/// 2. where the floor just before the start (two 5 cm cells on the rail's line) lies inside the image, floor must
///    have been seen there (floor_cells): else something (a leaf, a dropout) hides the start, which may be nearer.
/// Without a projection (a cloud that is no pinhole image) the floor alone decides. camera_in_base: the cloud's
/// frame in base_link.
RailStartView railStartView(const std::vector<RailLine>& rails, const std::vector<float>& floor_cells,
                            const std::optional<CloudProjection>& projection, const Eigen::Isometry3d& camera_in_base,
                            const RailDetectorParams& p);

}  // namespace greenhouse_rail_nav
