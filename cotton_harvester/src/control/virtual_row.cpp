#include "cotton_harvester/control/virtual_row.h"

#include <cmath>

namespace cotton_harvester {
namespace control {

VirtualRow::VirtualRow(const VirtualRowParams& params) : params_(params), rng_(params.seed) {
  std::uniform_real_distribution<double> along(-params_.boll_spread_along_m, params_.boll_spread_along_m);
  std::uniform_real_distribution<double> across(-params_.boll_spread_across_m, params_.boll_spread_across_m);
  std::uniform_real_distribution<double> depth(params_.boll_min_depth_m, params_.boll_max_depth_m);
  for (int p = 0; p < params_.plants; ++p) {
    const double plant = params_.first_plant_m + p * params_.plant_spacing_m;
    for (int b = 0; b < params_.bolls_per_plant; ++b) {
      bolls_.push_back(Boll{plant + along(rng_), across(rng_), depth(rng_), true});
    }
  }
}

std::vector<BollSighting> VirtualRow::visibleBolls(double travel_m) const {
  std::vector<BollSighting> seen;
  for (const auto& boll : bolls_) {
    if (!boll.on_plant) continue;
    const double y = boll.along_m - travel_m;
    if (std::abs(y) > params_.view_half_length_m) continue;
    BollSighting sighting;
    sighting.position = Point3{boll.across_m, y, boll.depth_m};
    sighting.confidence = 0.9;
    const double reach_x = boll.across_m - params_.end_effector_x_home_m;
    sighting.reachable = boll.depth_m > 0.0 && boll.depth_m < params_.reach_max_depth_m && reach_x >= 0.0 &&
                         reach_x <= params_.arm_length_m;
    seen.push_back(sighting);
  }
  return seen;
}

Point3 VirtualRow::endEffector(double extension_m, double depth_m) const {
  return Point3{params_.end_effector_x_home_m + extension_m, params_.end_effector_y_m, depth_m};
}

int VirtualRow::brush(double travel_m, const Point3& end_effector) {
  std::uniform_real_distribution<double> chance(0.0, 1.0);
  int taken = 0;
  for (auto& boll : bolls_) {
    if (!boll.on_plant) continue;
    const double dx = boll.across_m - end_effector.x;
    const double dy = boll.along_m - travel_m - end_effector.y;
    const double dz = boll.depth_m - end_effector.z;
    if (std::sqrt(dx * dx + dy * dy + dz * dz) > params_.pick_tolerance_m) continue;
    if (chance(rng_) < params_.pick_success_probability) {
      boll.on_plant = false;
      ++taken;
    }
  }
  return taken;
}

int VirtualRow::remaining() const {
  int n = 0;
  for (const auto& boll : bolls_) n += boll.on_plant ? 1 : 0;
  return n;
}

}  // namespace control
}  // namespace cotton_harvester
