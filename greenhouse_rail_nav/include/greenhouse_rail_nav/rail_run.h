#pragma once

#include <string>
#include <vector>

namespace greenhouse_rail_nav {

/// Distance [m] to what lies straight ahead in a planar scan: the median of the finite returns within
/// ±half_width_rad of the scan's x axis. NaN when there is none (nothing seen ahead, or a bad scan).
double forwardRange(const std::vector<float>& ranges, double angle_min_rad, double angle_increment_rad,
                    double half_width_rad, double range_min_m, double range_max_m);

/// The drive along one rail set (greenhouse paper §V-A3): forward at the treatment speed until the lidar's
/// distance to the far wall says the end of the rail is reached, then back, slowing down after
/// `slow_fraction` of the driven length until the range finders sense the floor.
struct RailRunParams {
  double treat_speed_mps = 0.5;      ///< the paper's UV dose needs 0.5 m/s [m/s]
  double accel_mps2 = 0.5;           ///< [m/s^2]
  double end_wall_range_m = 1.3;     ///< stop when the far wall is this close to the lidar [m]
  double return_speed_mps = 0.5;     ///< [m/s]
  double slow_fraction = 0.9;        ///< slow down after this fraction of the driven length on the way back
  double slow_speed_mps = 0.12;      ///< [m/s]
  double max_rail_length_m = 150.0;  ///< a run longer than this is stopped as an error [m]

  std::string validate() const;
};

/// Speed [m/s] (>= 0, the caller sets the sign) on the way in: ramps up to the treatment speed, and brakes
/// so that it stops when the far wall reaches end_wall_range_m. `wall_range_m` may be NaN (no wall seen yet).
double inboundSpeed(const RailRunParams& p, double current_speed_mps, double wall_range_m, double dt_s);

/// Speed magnitude [m/s] on the way back after `reversed_m` of `driven_in_m`.
double returnSpeed(const RailRunParams& p, double current_speed_mps, double reversed_m, double driven_in_m,
                   double dt_s);

/// The speed held at cruise while treating, as the report gives it: odometry comes at its own rate, so over one
/// control tick the pose may not have moved at all, or moved twice; the speed is measured over windows of at least
/// window_s instead, and their mean and standard deviation reported. A tick off cruise (ramping, braking, a
/// safety stop) or without elapsed time drops the open window.
class CruiseSpeedMeter {
 public:
  explicit CruiseSpeedMeter(double window_s = 0.5) : window_s_(window_s) {}
  /// One control tick: `moved_m` [m] driven over `dt_s` [s], `cruising` when the commanded speed was the cruise
  /// speed.
  void add(bool cruising, double moved_m, double dt_s);
  int windows() const { return n_; }  ///< closed windows
  /// Mean and standard deviation of the windows' speeds [m/s]; false (outputs untouched) without a closed window.
  bool stats(double* mean_mps, double* std_mps) const;

 private:
  double window_s_;
  double open_m_ = 0.0, open_s_ = 0.0;
  double sum_ = 0.0, sum2_ = 0.0;
  int n_ = 0;
};

}  // namespace greenhouse_rail_nav
