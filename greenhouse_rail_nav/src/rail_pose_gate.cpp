#include "greenhouse_rail_nav/rail_pose_gate.h"

#include <cmath>

namespace greenhouse_rail_nav {

std::string RailPoseGateParams::validate() const {
  if (!(std::isfinite(max_step_xy_m) && max_step_xy_m > 0.0)) return "max_step_xy_m must be > 0 [m]";
  if (!(std::isfinite(max_step_yaw_rad) && max_step_yaw_rad > 0.0)) return "max_step_yaw_rad must be > 0 [rad]";
  if (frames_to_accept_jump < 1) return "frames_to_accept_jump must be >= 1";
  if (!(std::isfinite(reset_after_s) && reset_after_s > 0.0)) return "reset_after_s must be > 0 [s]";
  return "";
}

bool RailPoseGate::consistent(const thorvald_base::Pose2D& a, const thorvald_base::Pose2D& b) const {
  return std::abs(a.x - b.x) <= params_.max_step_xy_m && std::abs(a.y - b.y) <= params_.max_step_xy_m &&
         std::abs(thorvald_base::normalizeAngle(a.yaw - b.yaw)) <= params_.max_step_yaw_rad;
}

void RailPoseGate::reset() {
  accepted_.reset();
  pending_.reset();
  pending_count_ = 0;
  held_back_ = 0;
}

RailPoseGate::Verdict RailPoseGate::update(const thorvald_base::Pose2D& estimate, double stamp_s) {
  const bool stale = accepted_ && (stamp_s - accepted_stamp_s_ > params_.reset_after_s || stamp_s < accepted_stamp_s_);
  if (!accepted_ || stale || consistent(*accepted_, estimate)) {
    accepted_ = estimate;
    accepted_stamp_s_ = stamp_s;
    pending_.reset();
    pending_count_ = 0;
    held_back_ = 0;
    return Verdict::kAccepted;
  }
  // Inconsistent with the last accepted estimate: count how long the new pose holds still.
  if (pending_ && consistent(*pending_, estimate)) {
    ++pending_count_;
  } else {
    pending_count_ = 1;
  }
  pending_ = estimate;
  if (pending_count_ >= params_.frames_to_accept_jump) {
    accepted_ = estimate;
    accepted_stamp_s_ = stamp_s;
    pending_.reset();
    pending_count_ = 0;
    held_back_ = 0;
    return Verdict::kAcceptedJump;
  }
  ++held_back_;
  return Verdict::kHeldBack;
}

}  // namespace greenhouse_rail_nav
