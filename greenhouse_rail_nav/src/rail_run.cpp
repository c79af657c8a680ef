#include "greenhouse_rail_nav/rail_run.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace greenhouse_rail_nav {

double forwardRange(const std::vector<float>& ranges, double angle_min_rad, double angle_increment_rad,
                    double half_width_rad, double range_min_m, double range_max_m) {
  std::vector<double> ahead;
  if (!std::isfinite(angle_min_rad) || !std::isfinite(angle_increment_rad) || angle_increment_rad == 0.0)
    return std::numeric_limits<double>::quiet_NaN();
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    const double a = angle_min_rad + static_cast<double>(i) * angle_increment_rad;
    const double r = ranges[i];
    if (std::fabs(a) <= half_width_rad && std::isfinite(r) && r >= range_min_m && r <= range_max_m) ahead.push_back(r);
  }
  if (ahead.empty()) return std::numeric_limits<double>::quiet_NaN();
  auto mid = ahead.begin() + static_cast<std::ptrdiff_t>(ahead.size() / 2);
  std::nth_element(ahead.begin(), mid, ahead.end());
  return *mid;
}

std::string RailRunParams::validate() const {
  std::ostringstream e;
  if (!(treat_speed_mps > 0.0 && treat_speed_mps <= 2.0)) e << "treat_speed must be in (0, 2] [m/s]; ";
  if (!(return_speed_mps > 0.0 && return_speed_mps <= 2.0)) e << "return_speed must be in (0, 2] [m/s]; ";
  if (!(accel_mps2 > 0.0)) e << "accel must be > 0 [m/s^2]; ";
  if (!(end_wall_range_m > 0.0)) e << "end_wall_range must be > 0 [m]; ";
  if (!(slow_fraction > 0.0 && slow_fraction < 1.0)) e << "slow_fraction must be in (0, 1); ";
  if (!(slow_speed_mps > 0.0 && slow_speed_mps <= return_speed_mps)) e << "slow_speed must be in (0, return_speed]; ";
  if (!(max_rail_length_m > 0.0)) e << "max_rail_length must be > 0 [m]; ";
  return e.str();
}

namespace {
double rampTowards(double current, double target, double accel, double dt) {
  const double step = accel * std::max(dt, 0.0);
  return std::clamp(target, current - step, current + step);
}
}  // namespace

double inboundSpeed(const RailRunParams& p, double current, double wall_range_m, double dt_s) {
  double target = p.treat_speed_mps;
  if (std::isfinite(wall_range_m)) {
    const double to_go = wall_range_m - p.end_wall_range_m;
    target = to_go <= 0.0 ? 0.0 : std::min(target, std::sqrt(2.0 * p.accel_mps2 * to_go));
  }
  // Braking is never limited by the ramp: the wall distance already includes the braking profile.
  return target < current ? target : rampTowards(current, target, p.accel_mps2, dt_s);
}

double returnSpeed(const RailRunParams& p, double current, double reversed_m, double driven_in_m, double dt_s) {
  const double target = reversed_m >= p.slow_fraction * driven_in_m ? p.slow_speed_mps : p.return_speed_mps;
  return rampTowards(current, target, p.accel_mps2, dt_s);
}

void CruiseSpeedMeter::add(bool cruising, double moved_m, double dt_s) {
  if (!(dt_s > 0.0 && cruising)) {
    open_m_ = open_s_ = 0.0;
    return;
  }
  open_m_ += moved_m;
  open_s_ += dt_s;
  if (open_s_ < window_s_) return;
  const double speed = open_m_ / open_s_;
  sum_ += speed;
  sum2_ += speed * speed;
  ++n_;
  open_m_ = open_s_ = 0.0;
}

bool CruiseSpeedMeter::stats(double* mean_mps, double* std_mps) const {
  if (n_ <= 0) return false;
  *mean_mps = sum_ / n_;
  *std_mps = std::sqrt(std::max(0.0, sum2_ / n_ - *mean_mps * *mean_mps));
  return true;
}

}  // namespace greenhouse_rail_nav
