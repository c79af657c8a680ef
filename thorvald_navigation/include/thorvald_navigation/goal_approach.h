#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "thorvald_navigation/costmap.h"
#include "thorvald_navigation/grid_planner.h"
#include "thorvald_base/pose2d.h"

namespace thorvald_navigation {

/// A plan to a goal pose, or why there is none.
struct GoalPlan {
  bool ok = false;
  /// The refusal is for lidar obstacles only (they may move away: wait), not for the map or the keep-out zone.
  bool blocked_by_obstacle = false;
  std::vector<Eigen::Vector2d> path;  ///< start ... goal [m] (the first leg when `then_to_goal`)
  std::string error;
  /// How a differential robot drives it (choosePathDirection): backwards when `reverse`; with `then_to_goal` the path
  /// ends at `first_target` (the final approach's start, heading the goal's) and a straight leg forward to the goal
  /// follows. Forward and whole by default.
  bool reverse = false;
  bool then_to_goal = false;
  thorvald_base::Pose2D first_target;
  std::vector<Eigen::Vector2d> second_leg;  ///< with then_to_goal: forward to the goal (empty: the straight line)
  std::string warning;  ///< not empty: no direction keeps the footprint clear of the map (why); driven forward
};

/// Refuses a goal whose footprint overlaps a wall, unmapped space, the keep-out zone or an obstacle (with that reason),
/// plans with planPath, and ends a differential robot's path with its final approach (withFinalApproach;
/// `final_approach_m` 0: none).
GoalPlan planToGoal(const Costmap& costmap, const Footprint& footprint, const thorvald_base::Pose2D& start,
                    const thorvald_base::Pose2D& goal, const PlannerParams& planner, double final_approach_m);

/// A differential robot turning on the spot at the goal moves base_link by a few centimetres (its turning centre is
/// not exactly base_link on a real floor): its path ends with `length_m` straight along the goal's heading, so that
/// the final turn is small. The plan's points within that stretch are dropped. Unchanged when the stretch would put
/// the footprint on any blocked cell, or for an empty path or a length <= 0.
std::vector<Eigen::Vector2d> withFinalApproach(const Costmap& costmap, const Footprint& footprint,
                                               std::vector<Eigen::Vector2d> path, const thorvald_base::Pose2D& goal,
                                               double length_m);

/// How the robot approaches a goal again from where it settled outside the tolerances.
struct Approach {
  /// First leg: to `first_target` (the final approach's start, heading the goal's), driven backwards when `reverse`.
  std::vector<Eigen::Vector2d> first_leg;
  thorvald_base::Pose2D first_target;
  bool reverse = false;
  /// Whether a second leg follows, straight from first_target to the goal.
  bool then_to_goal = false;
  /// With then_to_goal: the second leg, driven forward from first_target to the goal (empty: the straight line).
  std::vector<Eigen::Vector2d> second_leg;
};

/// Differential robot with a free final approach: back straight off to its start (no half turn on the spot, which
/// would swing a long robot's rear round), then drive it again. Otherwise straight to the goal.
Approach approachAgain(const Costmap& costmap, const Footprint& footprint, const thorvald_base::Pose2D& pose,
                       const thorvald_base::Pose2D& goal, double final_approach_m, bool omnidirectional);

/// How a differential robot drives a planned path: forward, or backwards (its rear first) as far as the final
/// approach's start, so that no turn on the spot sweeps its footprint over a wall, the keep-out zone or unknown space.
/// A robot that pivots about its front axle sweeps its rear round a circle as large as the frame is long: beside a
/// wall a turn one way can be free where the other way is not.
struct PathDirection {
  bool ok = true;
  std::string error;  ///< when !ok: no direction clears the turns
  /// The legs to drive: the whole path forward (reverse false, then_to_goal false), or backwards to `first_target`
  /// (the final approach's start, heading the goal's) and then forward to the goal.
  Approach approach;
};

/// Sweeps the footprint polygon over the motions a differential robot makes on `path` against walls, the keep-out
/// zone and unknown space: the turns on the spot (from its heading to the way along the path's first 0.3 m, at every
/// corner of the path, and at the end to the goal's heading) and the straight legs between them with the footprint
/// oriented along them; forward first, then backwards, then backwards as far as a point of the path where the robot
/// can turn and forward from there (the first such point). A path that clears forward is driven forward. The cells the
/// start pose's footprint already stands on are not held against either direction until the footprint has left them
/// (the robot is there already); every other blocked cell is, so a turn that sweeps the frame further into a wall it
/// touches is refused. Omnidirectional robots and paths of fewer than 2 points: forward, unchecked.
PathDirection choosePathDirection(const Costmap& costmap, const Footprint& footprint,
                                  const thorvald_base::Pose2D& start, const std::vector<Eigen::Vector2d>& path,
                                  const thorvald_base::Pose2D& goal, bool omnidirectional);

struct ArrivalParams {
  double xy_tolerance_m = 0.02;
  double yaw_tolerance_rad = 0.015;
  int max_corrections = 3;  ///< renewed approaches before the goal fails
  std::string validate() const;
};

enum class ArrivalVerdict { kReached, kApproachAgain, kFailed };

struct ArrivalJudgement {
  ArrivalVerdict verdict = ArrivalVerdict::kFailed;
  double xy_err_m = 0.0, yaw_err_rad = 0.0;  ///< settled pose against the goal
  std::string reason;                        ///< for kFailed
};

/// Judges the pose the robot settled at against the goal's tolerances, counting the renewed approaches of one goal.
class ArrivalJudge {
 public:
  explicit ArrivalJudge(const ArrivalParams& params) : params_(params) {}
  /// A new goal: no correction made yet.
  void reset() { corrections_ = 0; }
  ArrivalJudgement judge(const thorvald_base::Pose2D& settled, const thorvald_base::Pose2D& goal);
  int corrections() const { return corrections_; }

 private:
  ArrivalParams params_;
  int corrections_ = 0;
};

}  // namespace thorvald_navigation
