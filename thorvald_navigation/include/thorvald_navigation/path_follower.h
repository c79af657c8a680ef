#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "thorvald_base/pose2d.h"
#include "thorvald_base/twist2d.h"

namespace thorvald_navigation {

struct FollowerParams {
  bool omnidirectional = false;  ///< true: translate in any direction while turning (4WD4WS); false: differential
  double max_speed_mps = 0.5;
  double max_yaw_rate_radps = 0.6;
  double max_accel_mps2 = 0.5;
  double max_yaw_accel_radps2 = 1.0;
  double lookahead_m = 0.6;          ///< carrot distance along the path [m]
  double xy_tolerance_m = 0.02;      ///< goal reached when base_link is this close... [m]
  double yaw_tolerance_rad = 0.015;  ///< ...and the heading this close [rad]
  double rotate_in_place_rad = 0.5;  ///< differential: turn on the spot when the carrot is this far off [rad]
  double position_gain = 1.5;        ///< speed per metre of remaining distance near the goal [1/s]
  double yaw_gain = 2.5;             ///< yaw rate per radian of heading error [1/s]
  double min_speed_mps = 0.02;       ///< creep speed for the last centimetres [m/s]
  /// The position is latched when base_link is within this fraction of xy_tolerance_m of the goal, or within the
  /// tolerance once the goal is no longer ahead (a differential robot cannot close a sideways offset by driving on):
  /// stopping at the first point inside the tolerance would leave every goal about xy_tolerance_m short [0..1].
  double arrive_fraction = 0.4;
  /// Time from a command to the base's response (drive controllers, the mux, the control cycle). The last
  /// centimetres and the final turn are ended early by what the base still moves after the stop command: this delay
  /// at the current speed, then the braking at the acceleration limit [s].
  double command_latency_s = 0.1;
  /// Slowest turn rate of the final turn: the base's wheels must still turn at it [rad/s].
  double min_yaw_rate_radps = 0.03;
  /// Turn direction changes in the final turn after which the robot stops as soon as it is inside the yaw tolerance
  /// (an overshooting base would otherwise dither round the target).
  int max_turn_reversals = 2;
  std::string validate() const;
};

enum class FollowState { kFollowing, kFinalTurn, kArrived };

/// What the follower is doing in its last step, for logs and diagnostics.
enum class FollowPhase {
  kIdle,        ///< no path, or arrived
  kTurnToPath,  ///< differential: turning on the spot towards the path
  kDrive,       ///< following the path
  kCreep,       ///< inside the position tolerance, closing in on the goal
  kFinalTurn,   ///< turning to the goal's heading where it stands
};
const char* followPhaseName(FollowPhase phase);

/// Tracks a planned path to a goal pose: pure-pursuit towards a carrot on the path (differential robots turn on
/// the spot first when the carrot is far off to the side, and slow down before such a corner so that they turn where
/// the path does; omnidirectional robots translate towards it and turn towards the goal heading at the same time),
/// then a final turn on the spot. Speeds are ramped by the acceleration limits, and every speed, turn rate and
/// stop is planned so that the limits can stop it at its target without overshoot. Once the position is within
/// tolerance it is latched, so the final turn cannot undo it.
class PathFollower {
 public:
  explicit PathFollower(const FollowerParams& params) : params_(params) {}

  /// `reverse`: a differential robot drives the path backwards (its rear first), e.g. backing straight off a goal to
  /// approach it again; ignored by an omnidirectional robot.
  void setPath(const std::vector<Eigen::Vector2d>& path, const thorvald_base::Pose2D& goal, bool reverse = false);
  /// Only the final turn to `goal`'s heading where the robot stands (its position is already within the tolerance).
  void turnTo(const thorvald_base::Pose2D& goal);
  /// How far the base still moves after a stop command at `speed`: command_latency_s at that speed, then braking
  /// at `accel` [m or rad].
  double coastDistance(double speed, double accel) const;
  /// Direction changes of the current final turn (a measure of dithering).
  int turnReversals() const { return turn_reversals_; }
  /// One control step: `pose` of base_link in the path's frame, `dt` since the last step [s].
  thorvald_base::Twist2D step(const thorvald_base::Pose2D& pose, double dt);
  FollowState state() const { return state_; }
  FollowPhase phase() const { return phase_; }
  bool reversing() const { return reverse_; }
  /// Index of the path segment the robot is closest to so far (progress never goes back).
  std::size_t progressIndex() const { return progress_; }
  void stop() { last_ = thorvald_base::Twist2D{}; }
  const thorvald_base::Twist2D& lastCommand() const { return last_; }

 private:
  struct Frame;
  /// Scales the command's forward speed by the frame's sign (reversing) and limits it.
  thorvald_base::Twist2D output(const Frame& f, thorvald_base::Twist2D t, double dt);
  /// A yaw rate that the acceleration limit can still bring to zero within `angle` [rad/s].
  double turnRate(double angle) const;
  /// Inside the xy tolerance: switches to the final turn, or (differential) fills `creep` and returns true.
  bool closeIn(const Frame& f, thorvald_base::Twist2D* creep);
  /// The turn on the spot to the goal's heading along a braking profile; arrives when the heading is within aim.
  thorvald_base::Twist2D finalTurn(const Frame& f, double dt);
  /// Towards the carrot at the speed that can still stop at the goal (omnidirectional directly, else pursue()).
  thorvald_base::Twist2D drive(const Frame& f, double dt);
  /// Differential: slows for a sharp corner, turns on the spot towards the carrot or follows a pure-pursuit arc.
  thorvald_base::Twist2D pursue(const Frame& f, const Eigen::Vector2d& to_target, double speed, double dt);
  Eigen::Vector2d carrot(const Eigen::Vector2d& p);
  /// Path length from the closest point (after carrot()) to the next corner a differential robot turns on the spot
  /// at (a heading change above rotate_in_place_rad); infinite when none is left [m].
  double distanceToCorner(const Eigen::Vector2d& p) const;
  /// Whether a differential robot turns on the spot at path_[i] (heading change above rotate_in_place_rad between
  /// legs of at least 2 kCornerReachM).
  bool sharpCorner(std::size_t i) const;
  /// A differential robot this close to a sharp corner has reached it and turns there [m].
  static constexpr double kCornerReachM = 0.05;
  thorvald_base::Twist2D limit(const thorvald_base::Twist2D& wanted, double dt);

  FollowerParams params_;
  std::vector<Eigen::Vector2d> path_;
  thorvald_base::Pose2D goal_;
  std::size_t progress_ = 0;
  FollowState state_ = FollowState::kArrived;
  FollowPhase phase_ = FollowPhase::kIdle;
  bool reverse_ = false;
  bool turning_ = false;           ///< differential: turning on the spot towards the carrot
  int turn_reversals_ = 0;         ///< direction changes of the final turn's command
  std::size_t passed_corner_ = 0;  ///< the last sharp corner the robot reached (0: none)
  /// A differential robot's turn on the spot ends when the carrot is this close to straight ahead [rad].
  static constexpr double kTurnDoneRad = 0.05;
  /// Share of the acceleration limits that the stops at the goal (position and final turn) brake with: below one
  /// half, their braking profile meets the linear slow-down (gain times distance) where that is within the limits.
  static constexpr double kBrakeShare = 0.45;
  thorvald_base::Twist2D last_;
};

}  // namespace thorvald_navigation
