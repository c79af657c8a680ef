#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "thorvald_base/pose2d.h"
#include "thorvald_base/twist2d.h"
#include "thorvald_navigation/costmap.h"
#include "thorvald_navigation/goal_approach.h"
#include "thorvald_navigation/grid_planner.h"
#include "thorvald_navigation/localization_gate.h"
#include "thorvald_navigation/path_follower.h"

namespace thorvald_navigation {

/// Settings of one goal's lifecycle (headland_navigator's parameters of the same names); validate() names the bad one.
struct GoalRunnerParams {
  FollowerParams follower;
  LocalizationGateParams gate;
  double planner_patience_s = 5.0;  ///< give up when no pose/plan for this long [s]
  double obstacle_wait_s = 10.0;    ///< give up when blocked by lidar obstacles for this long [s]
  double settle_time_s = 0.5;       ///< after arriving, stand still this long before judging the pose [s]
  int goal_corrections = 3;         ///< renewed approaches when the settled pose is outside the tolerances
  /// A pose that moves farther than this from one cycle to the next (a relocalisation), and a settled pose farther
  /// than this from the goal, are planned from again (the whole way, the footprint swept), not followed on or
  /// approached straight: the pose the plan was made on was wrong [m].
  double replan_distance_m = 0.5;
  std::string validate() const;
};

/// What the runner needs of the world, so that tests can put in their own: a plan to a goal, the legs of a renewed
/// approach, and whether a lidar obstacle stands on the path ahead.
struct GoalPlanners {
  /// A plan from `start` to `goal` (planToGoal's contract: refused with the reason, and whether only lidar obstacles
  /// refused it).
  std::function<GoalPlan(const thorvald_base::Pose2D& start, const thorvald_base::Pose2D& goal)> plan;
  /// How to approach `goal` again from `pose`, where the robot settled outside the tolerances (approachAgain's).
  std::function<Approach(const thorvald_base::Pose2D& pose, const thorvald_base::Pose2D& goal)> approach_again;
  /// Whether a lidar obstacle lies under the footprint along `path` ahead of `pose` from point `next_index` on,
  /// with the follower's `goal_yaw` [rad] and driving direction (`reversing`).
  std::function<bool(const thorvald_base::Pose2D& pose, const std::vector<Eigen::Vector2d>& path,
                     std::size_t next_index, double goal_yaw, bool reversing)>
      obstacle_ahead;
};

/// The navigator's planners on a costmap: planToGoal (a differential robot's path ends with `final_approach_m`
/// straight along the goal's heading) with the direction a differential robot drives it (choosePathDirection: a plan
/// backwards, or backwards to a turning point and forward; a plan no direction clears is driven forward as planned,
/// with the reason in GoalPlan::warning),
/// approachAgain, and sweptObstacleDistance over `obstacle_check_ahead_m` [m].
/// `costmap` is called at each use (the node replaces its costmap when a map arrives) and must return one then.
GoalPlanners costmapPlanners(std::function<const Costmap&()> costmap, const Footprint& footprint,
                             const PlannerParams& planner, double final_approach_m, double obstacle_check_ahead_m,
                             bool omnidirectional);

/// Where the goal stands after a call.
enum class GoalState {
  kIdle,       ///< no goal
  kActive,     ///< on its way, holding, blocked or settling
  kSucceeded,  ///< reached this call
  kAborted,    ///< failed this call (`reason` says why)
  kCancelled,  ///< cancelled this call
};

/// What to send to the base this call.
enum class DriveCommand {
  kNone,   ///< nothing (no goal, or the follower switched legs this cycle)
  kStop,   ///< a zero twist
  kTwist,  ///< `twist`, with the pose as the goal's feedback
};

/// A log line of the lifecycle (a new phase, a hold, a correction, the result); `warning` for the ones a user
/// should look at.
struct GoalNote {
  bool warning = false;
  std::string text;
};

/// The outcome of one call of GoalRunner.
struct GoalTick {
  GoalState state = GoalState::kIdle;
  DriveCommand command = DriveCommand::kNone;
  thorvald_base::Twist2D twist;
  bool new_plan = false;  ///< a plan was made this call: path() and goal() to publish
  std::string reason;     ///< why the goal was aborted
  std::vector<GoalNote> notes;
};

/// One input of the control cycle: the time, base_link's pose in the map frame when there is one (else why not),
/// and the time since the last cycle.
struct GoalRunnerInput {
  double now_s = 0.0;  ///< any monotonic clock, the one accept() and setLocalizerStatus() get [s]
  std::optional<thorvald_base::Pose2D> pose;
  std::string no_pose_reason;  ///< when there is no pose: the abort reason once planner_patience_s is over
  double dt_s = 0.05;          ///< since the last cycle [s]
};

/// Counters over the runner's life, for diagnostics.
struct GoalRunnerCounts {
  long plans = 0, reached = 0, obstacle_stops = 0, relocalisation_waits = 0;
};

/// The lifecycle of a navigation goal, without ROS: accept it, plan, follow the path (PathFollower), stop and replan
/// for obstacles ahead, hold while the localiser is lost (LocalizationGate), settle at the goal and judge the pose
/// (ArrivalJudge), approach again or turn again while it is outside the tolerances, and end with a result. Each
/// control cycle the caller passes the pose and gets the command to send and the goal's state. One goal at a time:
/// a new one replaces the current one. Single-threaded.
class GoalRunner {
 public:
  GoalRunner(const GoalRunnerParams& params, GoalPlanners planners);

  /// A new goal at `now_s`, replacing any other; aborted at once when the pose is not finite.
  GoalTick accept(const thorvald_base::Pose2D& goal, double now_s);
  /// Cancels the goal: the robot stops.
  GoalTick cancel();
  /// Aborts the goal with `reason` (e.g. a goal frame the caller could not transform): the robot stops.
  GoalTick abort(const std::string& reason);
  /// Forgets the goal without a command (its owner ended it elsewhere).
  void drop() { active_ = false; }
  /// One control cycle.
  GoalTick tick(const GoalRunnerInput& in);

  /// The localiser's status at `now_s` [s].
  void setLocalizerStatus(LocalizerState state, double now_s) { gate_.setStatus(state, now_s); }
  LocalizerState localizerState() const { return gate_.state(); }

  bool active() const { return active_; }
  /// Stopped for the localiser, and why.
  bool holding() const { return holding_; }
  const std::string& holdReason() const { return hold_reason_; }
  /// Stopped (or waiting to plan) for a lidar obstacle.
  bool blocked() const { return blocked_since_s_.has_value(); }
  const std::string& lastFailure() const { return last_failure_; }
  const GoalRunnerCounts& counts() const { return counts_; }
  const thorvald_base::Pose2D& goal() const { return goal_; }
  /// The path being followed (the last plan, or a correction's leg).
  const std::vector<Eigen::Vector2d>& path() const { return path_; }

 private:
  GoalTick noPose(const GoalRunnerInput& in);
  /// Applies the localisation gate's verdict: false (with the command in `out`) when the robot may not drive.
  bool gateAllows(const GateVerdict& v, GoalTick* out);
  /// Before driving: the gate, and the replanning it asks for once the localiser is back.
  bool mayDrive(double now_s, GoalTick* out);
  /// Plans from `pose` when needed; false with the command in `out` when there is no plan.
  bool planIfNeeded(const thorvald_base::Pose2D& pose, double now_s, GoalTick* out);
  GoalTick stopForObstacle(double now_s);
  void notePhase(const thorvald_base::Pose2D& pose, double now_s, GoalTick* out);
  /// The follower arrived: the next leg, settling, the gate at the goal, then the judgement.
  GoalTick arrived(const thorvald_base::Pose2D& pose, double now_s);
  GoalTick judgeArrival(const thorvald_base::Pose2D& pose, double now_s);
  GoalTick stopped(GoalState state = GoalState::kActive);

  GoalRunnerParams params_;
  GoalPlanners planners_;
  PathFollower follower_;
  ArrivalJudge arrival_;
  LocalizationGate gate_;
  thorvald_base::Pose2D goal_;
  std::vector<Eigen::Vector2d> path_;
  bool active_ = false, need_plan_ = false;
  double started_s_ = 0.0;
  std::optional<double> blocked_since_s_, arrived_at_s_;
  std::optional<thorvald_base::Pose2D> last_pose_;  ///< the last cycle's, within this goal
  bool to_pre_goal_ = false;                        ///< a correction is on its way to the start of the final approach
  Eigen::Vector2d pre_goal_{0.0, 0.0};
  std::vector<Eigen::Vector2d> next_leg_;  ///< after pre_goal_: the way on to the goal (empty: straight)
  FollowPhase last_phase_ = FollowPhase::kIdle;
  bool holding_ = false;  ///< stopped for the localiser
  std::string hold_reason_, last_failure_;
  GoalRunnerCounts counts_;
};

}  // namespace thorvald_navigation
