#pragma once

#include <string>

#include "thorvald_base/pose2d.h"
#include "greenhouse_rail_nav/rail_alignment.h"

namespace greenhouse_rail_nav {

/// Speed, acceleration and tolerance of the motions executed on odometry.
struct MotionLimits {
  double max_speed_mps = 0.25;          ///< [m/s]
  double max_turn_rate_rps = 0.5;       ///< [rad/s]
  double accel_mps2 = 0.4;              ///< [m/s^2]
  double turn_accel_rps2 = 1.0;         ///< [rad/s^2]
  double min_speed_mps = 0.02;          ///< slowest commanded speed before arriving (overcomes friction) [m/s]
  double min_turn_rate_rps = 0.04;      ///< [rad/s]
  double position_tolerance_m = 0.004;  ///< [m]
  double angle_tolerance_rad = 0.004;   ///< [rad]
  double heading_gain = 2.0;            ///< keeps translations straight [1/s]
  double stall_timeout_s = 4.0;         ///< no progress for this long: the motion fails [s]
  double response_time_s = 0.15;        ///< the base's lag from command to motion: braking starts this early [s]

  std::string validate() const;
};

/// Executes one MotionStep with odometry as feedback (the alignment manoeuvre, the rail search, driving on
/// and off the rails): a trapezoidal speed profile that ends on the target, heading held on translations,
/// and a stall check. ROS-free: the caller feeds odometry poses and times and sends the returned twist.
class OdometryMotion {
 public:
  explicit OdometryMotion(const MotionLimits& limits) : limits_(limits) {}

  struct Command {
    double linear_mps = 0.0;
    double angular_rps = 0.0;
    bool done = false;    ///< the target is reached (the twist is zero)
    bool failed = false;  ///< stalled or bad input (the twist is zero); `reason` says why
    std::string reason;
  };

  /// Starts `step` from the current odometry pose at time `t_s` [s].
  void start(const MotionStep& step, const thorvald_base::Pose2D& odom_pose, double t_s);
  /// The command for the current odometry pose at time `t_s` [s].
  Command update(const thorvald_base::Pose2D& odom_pose, double t_s);
  /// Signed distance [m] or angle [rad] still to go.
  double remaining() const { return step_.amount - progress_; }
  bool active() const { return active_; }

 private:
  double profile(double remaining, double elapsed, double max_rate, double accel, double min_rate) const;

  MotionLimits limits_;
  MotionStep step_;
  thorvald_base::Pose2D start_pose_, last_pose_;
  double progress_ = 0.0;
  double start_time_ = 0.0;
  double last_progress_time_ = 0.0, last_progress_value_ = 0.0;
  double last_command_ = 0.0;  ///< last commanded rate along the step (m/s or rad/s)
  /// The rate the base has reached by now, modelled as a first-order lag of response_time behind the commands
  /// (from rest at the start): what is still to come once the command drops to zero is this rate times
  /// response_time. Taking the commanded rate instead stopped short rotations at half their angle (a 0.03 rad
  /// rotation turned 0.016 rad), as the base had not yet reached the rate commanded.
  double rate_estimate_ = 0.0;
  double last_update_s_ = 0.0;
  double settle_from_s_ = -1.0;  ///< when the target was reached (< 0: not yet); done 2 response times later
  bool active_ = false;
};

}  // namespace greenhouse_rail_nav
