#pragma once

#include <random>
#include <vector>

#include "cotton_harvester/control/harvest_decision.h"

namespace cotton_harvester {
namespace control {

/// A simulated row of potted cotton plants as the downward camera would see it (the preliminary
/// experiment of §2.13: six plants 30 cm apart, three bolls each), standing in for perception when
/// the controllers are simulated. Positions along the row are measured from the camera at the
/// start of the run; the camera moves with the rover.
struct VirtualRowParams {
  int plants = 6;
  int bolls_per_plant = 3;
  double first_plant_m = 0.6;  ///< along the row, from the camera's start position
  double plant_spacing_m = 0.30;
  double boll_spread_along_m = 0.06;     ///< bolls of a plant scatter ± this along the row
  double boll_spread_across_m = 0.15;    ///< and ± this across (camera x)
  double boll_min_depth_m = 0.75;        ///< depth from the camera of the highest boll
  double boll_max_depth_m = 1.05;        ///< and of the lowest
  double view_half_length_m = 0.6;       ///< camera sees |y| below this
  double end_effector_y_m = 0.0;         ///< camera y of the end effector (fixed on the rover)
  double end_effector_x_home_m = -0.15;  ///< camera x of the end effector, horizontal axis retracted
  double arm_length_m = 0.6;             ///< horizontal axis travel
  double reach_max_depth_m = 1.17;       ///< lowest point of the end effector
  double pick_tolerance_m = 0.05;        ///< end effector this close to a boll while the brush runs
  double pick_success_probability = 0.85;
  unsigned seed = 11;
};

/// Where the simulated bolls are and whether the brush took them.
class VirtualRow {
 public:
  explicit VirtualRow(const VirtualRowParams& params = VirtualRowParams());

  /// Bolls in view (camera frame) for a camera `travel_m` along the row from its start.
  std::vector<BollSighting> visibleBolls(double travel_m) const;
  /// End effector in the camera frame for a horizontal extension and a depth [m].
  Point3 endEffector(double extension_m, double depth_m) const;
  /// Brush switched on with the end effector at `end_effector` (camera frame): each boll within
  /// the pick tolerance comes off with the pick success probability. Returns the bolls taken.
  int brush(double travel_m, const Point3& end_effector);

  int present() const { return static_cast<int>(bolls_.size()); }
  int remaining() const;
  const VirtualRowParams& params() const { return params_; }

 private:
  struct Boll {
    double along_m, across_m, depth_m;
    bool on_plant = true;
  };
  VirtualRowParams params_;
  std::vector<Boll> bolls_;
  std::mt19937 rng_;
};

}  // namespace control
}  // namespace cotton_harvester
