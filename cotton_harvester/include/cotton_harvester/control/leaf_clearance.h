#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace cotton_harvester {
namespace control {

/// Clearing leaves over a boll before a pick: when the last frame's cloud shows something between
/// `leaf_clearance_m` above the boll's top and its top, along the end-effector's sideways approach and within the
/// housing's width (at least `leaf_points_min` points), the arm first sweeps through that level `leaf_clearance_m`
/// higher to `clear_overshoot_m` past the boll (pushing the leaf aside), backs off to `clear_standoff_m` short of it,
/// goes down to the boll's top again, and a new frame locates the boll (nearest the target within
/// `redetect_radius_m`). Lengths [m], camera frame (x across the row, the arm's extension; z down).
struct LeafClearanceParams {
  double leaf_clearance_m = 0.06;
  double clear_overshoot_m = 0.04;
  double clear_standoff_m = 0.12;
  int leaf_points_min = 40;
  double redetect_radius_m = 0.07;
  double effector_half_m = 0.05;  ///< half side of the end-effector's housing
  std::string check() const;      ///< empty when sound
};

/// An organised cloud as bytes: float32 x, y, z at the given offsets of each point (camera frame [m], NaN: none).
struct CloudView {
  const std::uint8_t* data = nullptr;
  int rows = 0, cols = 0;
  std::size_t row_step = 0, point_step = 12;
  std::size_t x_offset = 0, y_offset = 4, z_offset = 8;
};

/// Points of every second row and column of `cloud` above the boll along the approach from the housing at camera x
/// `from_x` to `target_x`, between leaf_clearance_m above `depth_m` (the boll's top, where the housing is) and 12 mm
/// above it (stereo noise), within the housing's half side of y = 0 and beyond the housing's own footprint.
int pointsOverApproach(const CloudView& cloud, double from_x, double target_x, double depth_m,
                       const LeafClearanceParams& params);

}  // namespace control
}  // namespace cotton_harvester
