#include "greenhouse_rail_nav/odometry_motion.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace greenhouse_rail_nav {

std::string MotionLimits::validate() const {
  std::ostringstream e;
  auto positive = [&](double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v)) e << name << " must be > 0; ";
  };
  positive(max_speed_mps, "max_speed");
  positive(max_turn_rate_rps, "max_turn_rate");
  positive(accel_mps2, "accel");
  positive(turn_accel_rps2, "turn_accel");
  positive(position_tolerance_m, "position_tolerance");
  positive(angle_tolerance_rad, "angle_tolerance");
  positive(stall_timeout_s, "stall_timeout");
  if (!(response_time_s >= 0.0 && response_time_s < 2.0)) e << "response_time must be in [0, 2) [s]; ";
  if (!(min_speed_mps >= 0.0 && min_speed_mps < max_speed_mps)) e << "min_speed must be in [0, max_speed); ";
  if (!(min_turn_rate_rps >= 0.0 && min_turn_rate_rps < max_turn_rate_rps))
    e << "min_turn_rate must be in [0, max_turn_rate); ";
  if (!(heading_gain >= 0.0)) e << "heading_gain must be >= 0; ";
  return e.str();
}

void OdometryMotion::start(const MotionStep& step, const thorvald_base::Pose2D& odom_pose, double t_s) {
  step_ = step;
  start_pose_ = last_pose_ = odom_pose;
  progress_ = 0.0;
  start_time_ = last_progress_time_ = t_s;
  last_progress_value_ = 0.0;
  last_command_ = 0.0;
  rate_estimate_ = 0.0;
  last_update_s_ = t_s;
  settle_from_s_ = -1.0;
  active_ = true;
}

double OdometryMotion::profile(double remaining, double elapsed, double max_rate, double accel, double min_rate) const {
  // Ramp up from rest at `accel`, brake so that the speed reaches zero on the target.
  const double rate =
      std::min({max_rate, accel * std::max(elapsed, 0.0) + min_rate, std::sqrt(2.0 * accel * std::fabs(remaining))});
  return std::copysign(std::max(rate, min_rate), remaining);
}

OdometryMotion::Command OdometryMotion::update(const thorvald_base::Pose2D& pose, double t_s) {
  Command c;
  if (!active_) {
    c.done = true;
    return c;
  }
  if (!std::isfinite(pose.x) || !std::isfinite(pose.y) || !std::isfinite(pose.yaw) || !std::isfinite(t_s)) {
    active_ = false;
    c.failed = true;
    c.reason = "odometry is not finite";
    return c;
  }
  const bool rotate = step_.kind == MotionStep::Kind::kRotate;
  if (rotate) {
    progress_ += thorvald_base::normalizeAngle(pose.yaw - last_pose_.yaw);  // unwrapped: rotations beyond pi add up
  } else {
    progress_ = (pose.position() - start_pose_.position()).dot(start_pose_.heading());
  }
  last_pose_ = pose;
  if (settle_from_s_ >= 0.0) {
    // Stopped: zero twist until the base has come to rest, so that the next step (whose heading hold takes the
    // heading it starts at) does not cut off the end of this one.
    if (t_s - settle_from_s_ >= 2.0 * limits_.response_time_s) {
      active_ = false;
      c.done = true;
    }
    return c;
  }
  // What is still to go once the motion already under way has come through (the base lags the command).
  const double dt = std::max(0.0, t_s - last_update_s_);
  last_update_s_ = t_s;
  rate_estimate_ += (limits_.response_time_s > 0.0 ? 1.0 - std::exp(-dt / limits_.response_time_s) : 1.0) *
                    (last_command_ - rate_estimate_);
  // Coming through: the lower of the commanded and the modelled rate. While speeding up the base is below the
  // command; while braking the command is below the base, and the profile's braking already takes the rest.
  const double coming = std::min(std::fabs(last_command_), std::fabs(rate_estimate_));
  const double rem = remaining() - std::copysign(coming, last_command_) * limits_.response_time_s;
  const double tol = rotate ? limits_.angle_tolerance_rad : limits_.position_tolerance_m;
  if (std::fabs(rem) <= tol || (rem * step_.amount < 0.0)) {  // reached or about to be: stop
    last_command_ = 0.0;
    settle_from_s_ = t_s;
    if (limits_.response_time_s > 0.0) return c;
    active_ = false;
    c.done = true;
    return c;
  }
  if (std::fabs(progress_ - last_progress_value_) > 2.0 * tol) {
    last_progress_value_ = progress_;
    last_progress_time_ = t_s;
  } else if (t_s - last_progress_time_ > limits_.stall_timeout_s) {
    active_ = false;
    c.failed = true;
    std::ostringstream r;
    r << "no progress for " << limits_.stall_timeout_s << " s with " << rem << (rotate ? " rad" : " m") << " to go ("
      << step_.label << ")";
    c.reason = r.str();
    return c;
  }
  const double elapsed = t_s - start_time_;
  if (rotate) {
    c.angular_rps =
        profile(rem, elapsed, limits_.max_turn_rate_rps, limits_.turn_accel_rps2, limits_.min_turn_rate_rps);
  } else {
    c.linear_mps = profile(rem, elapsed, limits_.max_speed_mps, limits_.accel_mps2, limits_.min_speed_mps);
    const double heading_error = thorvald_base::normalizeAngle(start_pose_.yaw - pose.yaw);
    c.angular_rps =
        std::clamp(limits_.heading_gain * heading_error, -limits_.max_turn_rate_rps, limits_.max_turn_rate_rps);
  }
  last_command_ = rotate ? c.angular_rps : c.linear_mps;
  return c;
}

}  // namespace greenhouse_rail_nav
