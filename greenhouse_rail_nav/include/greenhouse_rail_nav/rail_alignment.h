#pragma once

#include <string>
#include <vector>

#include "thorvald_base/pose2d.h"

namespace greenhouse_rail_nav {

/// One motion of an alignment manoeuvre, executed on odometry: a rotation in place by `amount` [rad] or a
/// straight translation along the robot's heading by `amount` [m] (negative: reverse).
struct MotionStep {
  enum class Kind { kRotate, kTranslate };
  Kind kind = Kind::kRotate;
  double amount = 0.0;
  std::string label;  ///< what the step is for, for logs ("rotate to align", "reverse", ...)
};

/// Where the robot should stand before it enters a rail set, and how far it may turn on the way there
/// (greenhouse paper §V-A2: rotate to align, reverse, rotate towards the rails, drive forward, rotate to align).
struct AlignmentParams {
  double approach_x_m = -0.8;  ///< desired base_link x in the rail frame (in front of the rail start) [m]
  double max_turn_rad = 0.6;   ///< largest heading change towards the rails' centre line [rad]
  /// Length of the diagonal leg that takes out a sideways offset (the robot reverses as far as it needs): the turn
  /// towards the centre line is atan(|y| / run_up), at most max_turn. A small turn sweeps little of the frame
  /// sideways: at a rail set 0.8 m from a side wall a 0.6 rad turn for a 4 cm offset swept the frame's rear corner
  /// into the wall; 0.13 rad sweeps its corners about 7 cm out [m].
  double run_up_m = 0.3;
  double y_limit_m = 0.02;          ///< |y| allowed for entering (the rail wheels tolerate about ±0.03 m) [m]
  double yaw_limit_rad = 0.02;      ///< |yaw| allowed for entering [rad]
  double x_window_m = 0.35;         ///< |x - approach_x| allowed for entering when x is observed [m]
  double min_step_m = 0.005;        ///< translations shorter than this are left out [m]
  double min_rotation_rad = 0.003;  ///< rotations smaller than this are left out [rad]

  std::string validate() const;
};

/// True when the robot may start entering: y and yaw within the limits, and x within its window when the
/// detector observed x (when the rail start is out of the camera's view, x is not used).
bool withinEntryLimits(const thorvald_base::Pose2D& robot_in_rail, bool x_observed, const AlignmentParams& p);

/// The manoeuvre that brings base_link from `robot_in_rail` (its pose in the rail frame: x along the rails,
/// origin between the rail starts) to (approach_x, 0, 0). Rotations in place about base_link, so the robot
/// must be able to turn on the spot (differential or 4WD4WS). Steps too small to matter are left out; an
/// empty plan means the robot already stands where it should.
std::vector<MotionStep> planAlignment(const thorvald_base::Pose2D& robot_in_rail, const AlignmentParams& p);

/// The pose the plan ends at when executed exactly (for tests and for logging the expected result).
thorvald_base::Pose2D applyPlan(const thorvald_base::Pose2D& start, const std::vector<MotionStep>& plan);

/// The search for rails that the camera does not see (§V-A2): rotations in place that turn the robot
/// alternately counter-clockwise and clockwise through growing angles, +step, -step, +2 step, -2 step, ...,
/// up to ±limit, then back to the start heading. Returned as relative rotations [rad] to execute in order.
std::vector<double> railSearchRotations(double step_rad, double limit_rad);

}  // namespace greenhouse_rail_nav
