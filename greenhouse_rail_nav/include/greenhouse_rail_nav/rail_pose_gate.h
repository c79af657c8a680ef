#pragma once

#include <optional>
#include <string>

#include "thorvald_base/pose2d.h"

namespace greenhouse_rail_nav {

/// The paper lets through only estimates consistent with the previous one. A real jump (the robot was
/// moved, or the first estimate was wrong) must not block forever: a new pose that stays consistent with
/// itself for frames_to_accept_jump frames in a row is accepted, and after reset_after_s without an
/// accepted estimate the next one is taken as it comes.
struct RailPoseGateParams {
  double max_step_xy_m = 0.10;     ///< largest accepted change in x or y between estimates [m]
  double max_step_yaw_rad = 0.05;  ///< largest accepted change in yaw [rad]
  int frames_to_accept_jump = 3;   ///< consistent frames after which a jump is accepted
  double reset_after_s = 2.0;      ///< [s]

  std::string validate() const;
};

class RailPoseGate {
 public:
  enum class Verdict { kAccepted, kAcceptedJump, kHeldBack };

  explicit RailPoseGate(const RailPoseGateParams& params) : params_(params) {}

  /// Feeds one estimate (base_link in the rail frame) taken at stamp_s [s].
  Verdict update(const thorvald_base::Pose2D& estimate, double stamp_s);
  /// Forgets the history (e.g. after the robot moved to another rail set).
  void reset();
  /// The last accepted estimate, if any.
  const std::optional<thorvald_base::Pose2D>& accepted() const { return accepted_; }
  /// Frames held back in a row.
  int heldBack() const { return held_back_; }

 private:
  bool consistent(const thorvald_base::Pose2D& a, const thorvald_base::Pose2D& b) const;

  RailPoseGateParams params_;
  std::optional<thorvald_base::Pose2D> accepted_;
  double accepted_stamp_s_ = 0.0;
  std::optional<thorvald_base::Pose2D> pending_;
  int pending_count_ = 0;
  int held_back_ = 0;
};

}  // namespace greenhouse_rail_nav
