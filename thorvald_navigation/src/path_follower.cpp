#include "thorvald_navigation/path_follower.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace thorvald_navigation {

std::string FollowerParams::validate() const {
  if (!(max_speed_mps > 0.0) || !(max_yaw_rate_radps > 0.0)) return "max speed and yaw rate must be > 0";
  if (!(max_accel_mps2 > 0.0) || !(max_yaw_accel_radps2 > 0.0)) return "acceleration limits must be > 0";
  if (!(lookahead_m > 0.0)) return "lookahead must be > 0";
  if (!(xy_tolerance_m > 0.0) || !(yaw_tolerance_rad > 0.0)) return "xy and yaw tolerances must be > 0";
  if (!(rotate_in_place_rad > 0.0 && rotate_in_place_rad <= thorvald_base::kPi))
    return "rotate_in_place must be in (0, pi]";
  if (!(position_gain > 0.0) || !(yaw_gain > 0.0)) return "gains must be > 0";
  if (!(min_speed_mps >= 0.0 && min_speed_mps <= max_speed_mps)) return "min_speed must be in [0, max_speed]";
  if (!(arrive_fraction > 0.0 && arrive_fraction <= 1.0)) return "arrive_fraction must be in (0, 1]";
  if (!(command_latency_s >= 0.0 && command_latency_s <= 2.0)) return "command_latency must be in [0, 2] s";
  if (!(min_yaw_rate_radps > 0.0 && min_yaw_rate_radps <= max_yaw_rate_radps))
    return "min_yaw_rate must be in (0, max_yaw_rate]";
  if (max_turn_reversals < 0) return "max_turn_reversals must be >= 0";
  return {};
}

const char* followPhaseName(FollowPhase phase) {
  switch (phase) {
    case FollowPhase::kIdle:
      return "idle";
    case FollowPhase::kTurnToPath:
      return "turning on the spot to the path";
    case FollowPhase::kDrive:
      return "driving";
    case FollowPhase::kCreep:
      return "closing in";
    case FollowPhase::kFinalTurn:
      return "final turn";
  }
  return "?";
}

void PathFollower::setPath(const std::vector<Eigen::Vector2d>& path, const thorvald_base::Pose2D& goal, bool reverse) {
  path_ = path;
  if (path_.empty() || (path_.back() - Eigen::Vector2d(goal.x, goal.y)).norm() > 1e-6)
    path_.emplace_back(goal.x, goal.y);
  goal_ = goal;
  progress_ = 0;
  state_ = FollowState::kFollowing;
  reverse_ = reverse && !params_.omnidirectional;
  turning_ = false;
  passed_corner_ = 0;
  turn_reversals_ = 0;
}

void PathFollower::turnTo(const thorvald_base::Pose2D& goal) {
  setPath({}, goal);
  state_ = FollowState::kFinalTurn;
}

double PathFollower::coastDistance(double speed, double accel) const {
  const double v = std::abs(speed);
  return v * params_.command_latency_s + v * v / (2.0 * accel);
}

double PathFollower::distanceToCorner(const Eigen::Vector2d& p) const {
  double d = 0.0;
  Eigen::Vector2d from = p;
  for (std::size_t i = progress_ + 1; i + 1 < path_.size(); ++i) {
    d += (path_[i] - from).norm();
    from = path_[i];
    if (sharpCorner(i) && i > passed_corner_ && (path_[i] - p).norm() > kCornerReachM) return d;
  }
  return std::numeric_limits<double>::infinity();
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
  // Walk lookahead metres along the path from the closest point. A differential robot's carrot waits at a sharp
  // corner until the robot is there: looking past it would make the robot turn early and cut the corner.
  double remaining = params_.lookahead_m;
  Eigen::Vector2d from = path_[best_seg] + best_t * (path_[best_seg + 1] - path_[best_seg]);
  for (std::size_t i = best_seg + 1; i < path_.size(); ++i) {
    const double seg = (path_[i] - from).norm();
    if (seg >= remaining) return from + (path_[i] - from) * (remaining / seg);
    if (!params_.omnidirectional && sharpCorner(i) && i > passed_corner_) {
      // Reached once, passed for good: the robot's turn on the spot moves base_link by a few centimetres (caster
      // wheels, the localiser), which must not send the carrot back to the corner.
      if ((path_[i] - p).norm() > kCornerReachM) return path_[i];
      passed_corner_ = i;
    }
    remaining -= seg;
    from = path_[i];
  }
  return path_.back();
}

bool PathFollower::sharpCorner(std::size_t i) const {
  if (i == 0 || i + 1 >= path_.size()) return false;
  const Eigen::Vector2d a = path_[i] - path_[i - 1], b = path_[i + 1] - path_[i];
  // Short legs (a staircase of grid cells in the plan) are smoothed by the pursuit, not turned at one by one.
  if (a.norm() < 2.0 * kCornerReachM || b.norm() < 2.0 * kCornerReachM) return false;
  return std::abs(thorvald_base::normalizeAngle(std::atan2(b.y(), b.x()) - std::atan2(a.y(), a.x()))) >
         params_.rotate_in_place_rad;
}

thorvald_base::Twist2D PathFollower::limit(const thorvald_base::Twist2D& wanted, double dt) {
  thorvald_base::Twist2D out = wanted;
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

/// What step() works with: the pose (turned round when reversing) and the goal, in the world and the robot's frame.
struct PathFollower::Frame {
  thorvald_base::Pose2D pose;
  Eigen::Vector2d p, goal;
  double dist = 0.0;     ///< to the goal [m]
  double yaw_err = 0.0;  ///< goal heading minus the robot's own (not the reversed) heading [rad]
  double sign = 1.0;     ///< -1 when reversing: the speed's sign flips at the end
  double c = 1.0, s = 0.0;
  Eigen::Vector2d toBody(const Eigen::Vector2d& w) const {
    return Eigen::Vector2d(c * w.x() + s * w.y(), -s * w.x() + c * w.y());
  }
};

thorvald_base::Twist2D PathFollower::step(const thorvald_base::Pose2D& pose_in, double dt) {
  if (state_ == FollowState::kArrived || path_.empty() || !pose_in.finite()) {
    phase_ = FollowPhase::kIdle;
    return limit(thorvald_base::Twist2D{}, dt);
  }
  // Reversing: the follower steers the robot's rear as if it were its front, and the speed's sign flips at the end.
  Frame f;
  f.sign = reverse_ ? -1.0 : 1.0;
  f.pose = thorvald_base::Pose2D{
      pose_in.x, pose_in.y, reverse_ ? thorvald_base::normalizeAngle(pose_in.yaw + thorvald_base::kPi) : pose_in.yaw};
  f.p = Eigen::Vector2d(f.pose.x, f.pose.y);
  f.goal = Eigen::Vector2d(goal_.x, goal_.y);
  f.dist = (f.goal - f.p).norm();
  f.yaw_err = thorvald_base::normalizeAngle(goal_.yaw - pose_in.yaw);
  f.c = std::cos(f.pose.yaw);
  f.s = std::sin(f.pose.yaw);
  if (state_ == FollowState::kFollowing && f.dist < params_.xy_tolerance_m) {
    thorvald_base::Twist2D creep;
    if (closeIn(f, &creep)) return output(f, creep, dt);
  }
  if (state_ == FollowState::kFinalTurn) return finalTurn(f, dt);
  return drive(f, dt);
}

thorvald_base::Twist2D PathFollower::output(const Frame& f, thorvald_base::Twist2D t, double dt) {
  t.vx *= f.sign;
  return limit(t, dt);
}

double PathFollower::turnRate(double angle) const {
  const double w =
      std::min({params_.max_yaw_rate_radps, std::max(params_.yaw_gain * std::abs(angle), params_.min_yaw_rate_radps),
                std::sqrt(2.0 * params_.max_yaw_accel_radps2 * 0.8 * std::abs(angle))});
  return std::copysign(w, angle);
}

bool PathFollower::closeIn(const Frame& f, thorvald_base::Twist2D* creep) {
  // Inside the tolerance: an omnidirectional robot closes in to near_m; a differential one creeps straight on
  // (no turn on the spot for a sideways offset it cannot remove) until the goal is less than near_m ahead.
  // The base goes on for a moment after the stop command: stop that much early, so that it halts near the goal.
  const double near_m = params_.arrive_fraction * params_.xy_tolerance_m;
  const double coast = coastDistance(std::hypot(last_.vx, last_.vy), params_.max_accel_mps2);
  const double ahead = f.toBody(f.goal - f.p).x();
  if (f.dist < near_m + (params_.omnidirectional ? coast : 0.0) ||
      (!params_.omnidirectional && ahead < near_m + coast)) {
    state_ = FollowState::kFinalTurn;
  } else if (!params_.omnidirectional) {
    phase_ = FollowPhase::kCreep;
    *creep = thorvald_base::Twist2D{};
    creep->vx = std::max(params_.min_speed_mps, params_.position_gain * ahead);
    return true;
  }
  return false;
}

thorvald_base::Twist2D PathFollower::finalTurn(const Frame& f, double dt) {
  phase_ = FollowPhase::kFinalTurn;
  // The turn rate falls along a braking profile that includes the base's delay, down to the slowest rate its
  // wheels still turn at; the stop command goes out when what the base turns after it (delay, then braking) brings
  // the heading to within arrive_fraction of the tolerance. After repeated reversals it stops as soon as it is
  // inside the tolerance.
  const double yaw_err = f.yaw_err;
  const double aim = params_.arrive_fraction * params_.yaw_tolerance_rad;
  const double a = kBrakeShare * params_.max_yaw_accel_radps2, lat = params_.command_latency_s;
  const double left = std::max(0.0, std::abs(yaw_err) - aim);
  const double profile =
      std::clamp(a * (std::sqrt(lat * lat + 2.0 * left / a) - lat), params_.min_yaw_rate_radps,
                 std::min(params_.max_yaw_rate_radps, std::max(params_.yaw_gain * left, params_.min_yaw_rate_radps)));
  const bool turning_towards = last_.wz * yaw_err > 0.0;
  const double coast =
      turning_towards ? coastDistance(std::min(std::abs(last_.wz), profile), params_.max_yaw_accel_radps2) : 0.0;
  const bool dithering = turn_reversals_ >= params_.max_turn_reversals;
  if (std::abs(yaw_err) <= aim + coast || (dithering && std::abs(yaw_err) < params_.yaw_tolerance_rad)) {
    state_ = FollowState::kArrived;
    phase_ = FollowPhase::kIdle;
    last_ = thorvald_base::Twist2D{};
    return last_;
  }
  thorvald_base::Twist2D t;
  t.wz = std::copysign(profile, yaw_err);
  if (last_.wz * t.wz < 0.0) ++turn_reversals_;
  if (params_.omnidirectional) {  // keep correcting small position drift while turning
    const Eigen::Vector2d b = f.toBody(f.goal - f.p) * params_.position_gain;
    t.vx = b.x();
    t.vy = b.y();
  }
  return limit(t, dt);
}

thorvald_base::Twist2D PathFollower::drive(const Frame& f, double dt) {
  const Eigen::Vector2d target = carrot(f.p);
  const Eigen::Vector2d to_target = target - f.p;
  // Speed that can still stop at the goal after the base's delay, and slows linearly in the last metres. The braking
  // profile uses kBrakeShare of the acceleration limit: where it meets the linear part, that part's deceleration
  // (position_gain times the speed) is then within the limit, so the ramp-limited command follows the profile
  // instead of lagging behind it and overshooting the goal.
  const double acc = kBrakeShare * params_.max_accel_mps2, lat = params_.command_latency_s;
  const double stop_speed = acc * (std::sqrt(lat * lat + 2.0 * f.dist / acc) - lat);
  const double speed =
      std::clamp(std::min(params_.position_gain * f.dist, stop_speed), params_.min_speed_mps, params_.max_speed_mps);
  phase_ = f.dist < params_.xy_tolerance_m ? FollowPhase::kCreep : FollowPhase::kDrive;
  if (!params_.omnidirectional) return pursue(f, to_target, speed, dt);
  thorvald_base::Twist2D t;
  const Eigen::Vector2d dir = to_target.norm() > 1e-9 ? Eigen::Vector2d(to_target.normalized()) : Eigen::Vector2d(0, 0);
  const Eigen::Vector2d b = f.toBody(dir * speed);
  t.vx = b.x();
  t.vy = b.y();
  t.wz = std::clamp(params_.yaw_gain * f.yaw_err, -params_.max_yaw_rate_radps, params_.max_yaw_rate_radps);
  return limit(t, dt);
}

thorvald_base::Twist2D PathFollower::pursue(const Frame& f, const Eigen::Vector2d& to_target, double speed, double dt) {
  // A differential robot stops at a sharp corner of the path to turn there on the spot, not past it.
  const double corner = distanceToCorner(f.p);
  if (std::isfinite(corner))
    speed = std::min(speed, std::max(params_.min_speed_mps, std::sqrt(2.0 * params_.max_accel_mps2 * 0.8 *
                                                                      std::max(0.0, corner - kCornerReachM))));
  const Eigen::Vector2d b = f.toBody(to_target);
  const double alpha = std::atan2(b.y(), b.x());
  thorvald_base::Twist2D t;
  // Close to the goal a differential robot that is slightly off to the side would circle; it backs or turns.
  // A turn on the spot goes on until the robot faces the carrot (hysteresis): stopping it at rotate_in_place_rad
  // would leave the pursuit a curve that ends the path with a heading error.
  const double turn_until = std::min(kTurnDoneRad, 0.5 * params_.rotate_in_place_rad);
  turning_ = std::abs(alpha) > params_.rotate_in_place_rad || (turning_ && std::abs(alpha) > turn_until);
  if (turning_) {
    if (f.dist < 0.1 && std::abs(alpha) > thorvald_base::kPi - params_.rotate_in_place_rad) {
      turning_ = false;
      t.vx = -std::max(params_.min_speed_mps, params_.position_gain * f.dist);  // just passed it: back up
      return output(f, t, dt);
    }
    phase_ = FollowPhase::kTurnToPath;
    t.wz = turnRate(alpha);
    return output(f, t, dt);
  }
  const double l2 = std::max(b.squaredNorm(), 1e-6);
  t.vx = speed * std::cos(alpha);
  t.wz = 2.0 * t.vx * b.y() / l2;  // pure pursuit curvature
  if (std::abs(t.wz) > params_.max_yaw_rate_radps) {
    t.vx *= params_.max_yaw_rate_radps / std::abs(t.wz);
    t.wz = std::copysign(params_.max_yaw_rate_radps, t.wz);
  }
  return output(f, t, dt);
}

}  // namespace thorvald_navigation
