#include "thorvald_navigation/path_follower.h"

#include <algorithm>
#include <cmath>

namespace thorvald_navigation {

std::string FollowerParams::validate() const {
  if (!(max_speed_mps > 0.0) || !(max_yaw_rate_radps > 0.0)) return "max speed and yaw rate must be > 0";
  if (!(max_accel_mps2 > 0.0) || !(max_yaw_accel_radps2 > 0.0)) return "acceleration limits must be > 0";
  if (!(lookahead_m > 0.0)) return "lookahead must be > 0";
  if (!(xy_tolerance_m > 0.0) || !(yaw_tolerance_rad > 0.0)) return "xy and yaw tolerances must be > 0";
  if (!(rotate_in_place_rad > 0.0 && rotate_in_place_rad <= kPi)) return "rotate_in_place must be in (0, pi]";
  if (!(position_gain > 0.0) || !(yaw_gain > 0.0)) return "gains must be > 0";
  if (!(min_speed_mps >= 0.0 && min_speed_mps <= max_speed_mps)) return "min_speed must be in [0, max_speed]";
  if (!(arrive_fraction > 0.0 && arrive_fraction <= 1.0)) return "arrive_fraction must be in (0, 1]";
  return {};
}

void PathFollower::setPath(const std::vector<Eigen::Vector2d>& path, const Pose2D& goal) {
  path_ = path;
  if (path_.empty() || (path_.back() - Eigen::Vector2d(goal.x, goal.y)).norm() > 1e-6)
    path_.emplace_back(goal.x, goal.y);
  goal_ = goal;
  progress_ = 0;
  state_ = FollowState::kFollowing;
}

Eigen::Vector2d PathFollower::carrot(const Eigen::Vector2d& p) {
  // Closest point on the path's segments from the current segment on (progress never goes back).
  double best = 1e18, best_t = 0.0;
  std::size_t best_seg = progress_;
  for (std::size_t i = progress_; i + 1 < path_.size(); ++i) {
    const Eigen::Vector2d e = path_[i + 1] - path_[i];
    const double len2 = e.squaredNorm();
    const double t = len2 > 1e-12 ? std::clamp((p - path_[i]).dot(e) / len2, 0.0, 1.0) : 0.0;
    const double d = (path_[i] + t * e - p).norm();
    if (d < best) {
      best = d;
      best_seg = i;
      best_t = t;
    }
  }
  progress_ = best_seg;
  if (path_.size() < 2) return path_.back();
  // Walk lookahead metres along the path from the closest point.
  double remaining = params_.lookahead_m;
  Eigen::Vector2d from = path_[best_seg] + best_t * (path_[best_seg + 1] - path_[best_seg]);
  for (std::size_t i = best_seg + 1; i < path_.size(); ++i) {
    const double seg = (path_[i] - from).norm();
    if (seg >= remaining) return from + (path_[i] - from) * (remaining / seg);
    remaining -= seg;
    from = path_[i];
  }
  return path_.back();
}

Twist2D PathFollower::limit(const Twist2D& wanted, double dt) {
  Twist2D out = wanted;
  const double v = std::hypot(out.vx, out.vy);
  if (v > params_.max_speed_mps) {
    out.vx *= params_.max_speed_mps / v;
    out.vy *= params_.max_speed_mps / v;
  }
  out.wz = std::clamp(out.wz, -params_.max_yaw_rate_radps, params_.max_yaw_rate_radps);
  if (dt > 0.0) {
    const double dv = params_.max_accel_mps2 * dt, dw = params_.max_yaw_accel_radps2 * dt;
    out.vx = std::clamp(out.vx, last_.vx - dv, last_.vx + dv);
    out.vy = std::clamp(out.vy, last_.vy - dv, last_.vy + dv);
    out.wz = std::clamp(out.wz, last_.wz - dw, last_.wz + dw);
  }
  last_ = out;
  return out;
}

Twist2D PathFollower::step(const Pose2D& pose, double dt) {
  if (state_ == FollowState::kArrived || path_.empty() || !pose.finite()) return limit(Twist2D{}, dt);
  const Eigen::Vector2d p(pose.x, pose.y), goal(goal_.x, goal_.y);
  const double dist = (goal - p).norm();
  const double yaw_err = normalizeAngle(goal_.yaw - pose.yaw);
  const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
  auto toBody = [&](const Eigen::Vector2d& w) {
    return Eigen::Vector2d(c * w.x() + s * w.y(), -s * w.x() + c * w.y());
  };
  const double near_m = params_.arrive_fraction * params_.xy_tolerance_m;
  if (state_ == FollowState::kFollowing && dist < params_.xy_tolerance_m) {
    // Inside the tolerance: an omnidirectional robot closes in to near_m; a differential one creeps straight on
    // (no turn on the spot for a sideways offset it cannot remove) until the goal is less than near_m ahead.
    const double ahead = toBody(goal - p).x();
    if (dist < near_m || (!params_.omnidirectional && ahead < near_m)) {
      state_ = FollowState::kFinalTurn;
    } else if (!params_.omnidirectional) {
      Twist2D t;
      t.vx = std::max(params_.min_speed_mps, params_.position_gain * ahead);
      return limit(t, dt);
    }
  }
  if (state_ == FollowState::kFinalTurn) {
    if (std::abs(yaw_err) < params_.yaw_tolerance_rad) {
      state_ = FollowState::kArrived;
      last_ = Twist2D{};
      return last_;
    }
    Twist2D t;
    // Slow near the target so that the acceleration limit does not overshoot it.
    const double wz = std::max(params_.yaw_gain * std::abs(yaw_err), 0.05);
    t.wz = std::copysign(std::min(wz, std::sqrt(2.0 * params_.max_yaw_accel_radps2 * std::abs(yaw_err))), yaw_err);
    if (params_.omnidirectional) {  // keep correcting small position drift while turning
      const Eigen::Vector2d b = toBody(goal - p) * params_.position_gain;
      t.vx = b.x();
      t.vy = b.y();
    }
    return limit(t, dt);
  }
  const Eigen::Vector2d target = carrot(p);
  const Eigen::Vector2d to_target = target - p;
  // Speed that can still stop at the goal with the acceleration limit, and slows linearly in the last metres.
  const double stop_speed = std::sqrt(2.0 * params_.max_accel_mps2 * 0.8 * dist);
  const double speed =
      std::clamp(std::min(params_.position_gain * dist, stop_speed), params_.min_speed_mps, params_.max_speed_mps);
  Twist2D t;
  if (params_.omnidirectional) {
    const Eigen::Vector2d dir =
        to_target.norm() > 1e-9 ? Eigen::Vector2d(to_target.normalized()) : Eigen::Vector2d(0, 0);
    const Eigen::Vector2d b = toBody(dir * speed);
    t.vx = b.x();
    t.vy = b.y();
    t.wz = std::clamp(params_.yaw_gain * yaw_err, -params_.max_yaw_rate_radps, params_.max_yaw_rate_radps);
    return limit(t, dt);
  }
  const Eigen::Vector2d b = toBody(to_target);
  const double alpha = std::atan2(b.y(), b.x());
  // Close to the goal a differential robot that is slightly off to the side would circle; it backs or turns.
  if (std::abs(alpha) > params_.rotate_in_place_rad) {
    if (dist < 0.1 && std::abs(alpha) > kPi - params_.rotate_in_place_rad) {
      t.vx = -std::max(params_.min_speed_mps, params_.position_gain * dist);  // just passed it: back up
      return limit(t, dt);
    }
    t.wz = std::copysign(std::min(params_.max_yaw_rate_radps, params_.yaw_gain * std::abs(alpha)), alpha);
    return limit(t, dt);
  }
  const double l2 = std::max(b.squaredNorm(), 1e-6);
  t.vx = speed * std::cos(alpha);
  t.wz = 2.0 * t.vx * b.y() / l2;  // pure pursuit curvature
  if (std::abs(t.wz) > params_.max_yaw_rate_radps) {
    t.vx *= params_.max_yaw_rate_radps / std::abs(t.wz);
    t.wz = std::copysign(params_.max_yaw_rate_radps, t.wz);
  }
  return limit(t, dt);
}

}  // namespace thorvald_navigation
