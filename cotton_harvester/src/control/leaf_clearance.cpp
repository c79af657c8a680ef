#include "cotton_harvester/control/leaf_clearance.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace cotton_harvester {
namespace control {

std::string LeafClearanceParams::check() const {
  const std::pair<const char*, double> values[] = {{"leaf_clearance_m", leaf_clearance_m},
                                                   {"clear_overshoot_m", clear_overshoot_m},
                                                   {"clear_standoff_m", clear_standoff_m},
                                                   {"redetect_radius_m", redetect_radius_m}};
  for (const auto& [key, v] : values)
    if (!(v >= 0.0) || !std::isfinite(v)) return std::string(key) + ": expected >= 0";
  if (!(effector_half_m > 0.0) || !std::isfinite(effector_half_m)) return "effector_half_m: expected > 0";
  if (leaf_points_min < 1) return "leaf_points_min: expected >= 1";
  return "";
}

int pointsOverApproach(const CloudView& cloud, double from_x, double target_x, double depth_m,
                       const LeafClearanceParams& params) {
  if (!cloud.data || cloud.rows <= 0 || cloud.cols <= 0) return 0;
  if (!std::isfinite(from_x) || !std::isfinite(target_x) || !std::isfinite(depth_m)) return 0;
  const double half = params.effector_half_m;
  const double x_low = std::min(from_x, target_x) - half, x_high = std::max(from_x, target_x) + half;
  const double z_low = depth_m - params.leaf_clearance_m, z_high = depth_m - 0.012;
  int n = 0;
  for (int v = 0; v < cloud.rows; v += 2) {
    const std::uint8_t* row = cloud.data + static_cast<std::size_t>(v) * cloud.row_step;
    for (int u = 0; u < cloud.cols; u += 2) {
      const std::uint8_t* point = row + static_cast<std::size_t>(u) * cloud.point_step;
      float x, y, z;
      std::memcpy(&z, point + cloud.z_offset, sizeof(float));
      if (!(z > z_low && z < z_high)) continue;  // also false for NaN
      std::memcpy(&x, point + cloud.x_offset, sizeof(float));
      std::memcpy(&y, point + cloud.y_offset, sizeof(float));
      if (std::abs(y) > half || x < x_low || x > x_high) continue;
      if (std::abs(x - from_x) <= half) continue;  // the housing's own top face
      ++n;
    }
  }
  return n;
}

}  // namespace control
}  // namespace cotton_harvester
