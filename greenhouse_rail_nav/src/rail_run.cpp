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
  if (!(rail_end_margin_m >= 0.0 && rail_end_margin_m <= 5.0)) e << "rail_end_margin must be in [0, 5] [m]; ";
  if (!(wall_guard_range_m > 0.0)) e << "wall_guard_range must be > 0 [m]; ";
  if (!(lamp_length_m > 0.0 && lamp_length_m <= 5.0)) e << "lamp_length must be in (0, 5] [m]; ";
  if (!(std::fabs(lamp_offset_m) <= 5.0)) e << "lamp_offset must be in [-5, 5] [m]; ";
  if (!(return_overrun_m >= 0.0 && return_overrun_m <= 10.0)) e << "return_overrun must be in [0, 10] [m]; ";
  if (!(return_overrun_fraction >= 0.0 && return_overrun_fraction <= 1.0))
    e << "return_overrun_fraction must be in [0, 1]; ";
  if (!(return_stall_s > 0.0 && return_stall_s <= 60.0)) e << "return_stall_time must be in (0, 60] [s]; ";
  if (!(return_max_heading_error_rad > 0.0 && return_max_heading_error_rad <= 3.14))
    e << "return_max_heading_error must be in (0, 3.14] [rad]; ";
  return e.str();
}

namespace {
double rampTowards(double current, double target, double accel, double dt) {
  const double step = accel * std::max(dt, 0.0);
  return std::clamp(target, current - step, current + step);
}

/// Ramps up to the treatment speed, braking to stop after `to_go_m` (infinite: no stop ahead).
double speedToStop(const RailRunParams& p, double current, double to_go_m, double dt_s) {
  double target = p.treat_speed_mps;
  if (std::isfinite(to_go_m)) target = to_go_m <= 0.0 ? 0.0 : std::min(target, std::sqrt(2.0 * p.accel_mps2 * to_go_m));
  // Braking is never limited by the ramp: the distance to go already includes the braking profile.
  return target < current ? target : rampTowards(current, target, p.accel_mps2, dt_s);
}
}  // namespace

double inboundSpeed(const RailRunParams& p, double current, double wall_range_m, double dt_s) {
  const double inf = std::numeric_limits<double>::infinity();
  return speedToStop(p, current, std::isfinite(wall_range_m) ? wall_range_m - p.end_wall_range_m : inf, dt_s);
}

double rowStopPosition(const RailRunParams& p, double row_length_m) {
  const double lamps_past = row_length_m - (p.lamp_offset_m - 0.5 * p.lamp_length_m);  // rear edge at the end
  return std::min(lamps_past, row_length_m - p.rail_end_margin_m);
}

double inboundSpeedToRowEnd(const RailRunParams& p, double current, double row_position_m, double row_length_m,
                            double wall_range_m, double dt_s) {
  double to_go = rowStopPosition(p, row_length_m) - row_position_m;
  if (std::isfinite(wall_range_m)) to_go = std::min(to_go, wall_range_m - p.wall_guard_range_m);
  return speedToStop(p, current, to_go, dt_s);
}

RowLitCoverage::RowLitCoverage(const RailRunParams& p, double row_length_m, double bin_m)
    : rear_m_(p.lamp_offset_m - 0.5 * p.lamp_length_m),
      front_m_(p.lamp_offset_m + 0.5 * p.lamp_length_m),
      row_length_m_(std::max(0.0, row_length_m)),
      bin_m_(bin_m),
      lit_(static_cast<std::size_t>(std::ceil(row_length_m_ / bin_m - 1e-9)), false) {}

void RowLitCoverage::add(double from_m, double to_m, bool on) {
  if (!on || lit_.empty() || !std::isfinite(from_m) || !std::isfinite(to_m)) return;
  // The lit stretch swept from the lower position's rear edge to the higher one's front edge, within the row.
  const double lo = std::max(0.0, std::min(from_m, to_m) + rear_m_);
  const double hi = std::min(row_length_m_, std::max(from_m, to_m) + front_m_);
  if (hi <= lo) return;
  const auto first = static_cast<std::size_t>(std::floor(lo / bin_m_));
  const auto last = std::min(lit_.size() - 1, static_cast<std::size_t>(std::floor(hi / bin_m_ - 1e-9)));
  for (std::size_t i = first; i <= last; ++i) lit_[i] = true;
}

double RowLitCoverage::fraction() const {
  if (lit_.empty()) return 1.0;
  double lit = 0.0;
  for (std::size_t i = 0; i < lit_.size(); ++i)
    if (lit_[i]) lit += std::min(bin_m_, row_length_m_ - static_cast<double>(i) * bin_m_);
  return lit / row_length_m_;
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

ReturnWatch::ReturnWatch(const RailRunParams& p, const thorvald_base::Pose2D& entry, double driven_in_m, double now_s)
    : p_(p), entry_(entry), last_(entry), driven_in_m_(driven_in_m), best_along_(driven_in_m), progress_at_s_(now_s) {}

std::string ReturnWatch::update(const thorvald_base::Pose2D& odom, bool on_rails, bool driving, double now_s) {
  constexpr double kProgressM = 0.05;  // nearer by at least this counts as progress (odometry's jitter below it)
  if (started_) backed_m_ += (odom.position() - last_.position()).norm();
  started_ = true;
  last_ = odom;
  const double along = (odom.position() - entry_.position()).dot(entry_.heading());
  if (along < best_along_ - kProgressM || !driving) {
    best_along_ = std::min(best_along_, along);
    progress_at_s_ = now_s;
  }
  std::ostringstream o;
  o.setf(std::ios::fixed);
  o.precision(2);
  const double limit_m = driven_in_m_ * (1.0 + p_.return_overrun_fraction) + p_.return_overrun_m;
  if (backed_m_ > limit_m) {
    o << "backed " << backed_m_ << " m by odometry after driving " << driven_in_m_
      << " m in, without reaching the stored pose (" << along << " m from it along the rails' line)";
    return o.str();
  }
  if (now_s - progress_at_s_ > p_.return_stall_s) {
    o << "no progress towards the stored pose for " << now_s - progress_at_s_ << " s while driving back (" << along
      << " m from it along the rails' line)";
    return o.str();
  }
  const double heading_error = thorvald_base::normalizeAngle(odom.yaw - entry_.yaw);
  if (!on_rails && std::fabs(heading_error) > p_.return_max_heading_error_rad) {
    o.precision(0);
    o << "off the rails, the heading is " << heading_error * 180.0 / M_PI
      << " deg off the rails' line by odometry (at most " << p_.return_max_heading_error_rad * 180.0 / M_PI << " deg)";
    return o.str();
  }
  return {};
}

}  // namespace greenhouse_rail_nav
