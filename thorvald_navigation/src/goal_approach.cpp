#include "thorvald_navigation/goal_approach.h"

#include <cmath>
#include <cstdio>

namespace thorvald_navigation {

GoalPlan planToGoal(const Costmap& costmap, const Footprint& footprint, const Pose2D& start, const Pose2D& goal,
                    const PlannerParams& planner, double final_approach_m) {
  GoalPlan out;
  if (!start.finite() || !goal.finite()) {
    out.error = "goal refused: start or goal is not finite";
    return out;
  }
  const Blocker at_goal = costmap.footprintBlocker(goal, footprint);
  if (at_goal != Blocker::kNone) {
    out.error = std::string("goal refused: the robot would overlap ") + blockerName(at_goal);
    out.blocked_by_obstacle = at_goal == Blocker::kObstacle;
    return out;
  }
  const PlanResult r = planPath(costmap, {start.x, start.y}, {goal.x, goal.y}, planner);
  if (!r.ok) {
    out.error = "goal refused: " + r.error;
    const Eigen::Vector2i c = costmap.geometry().cellOf({goal.x, goal.y});
    if (costmap.geometry().inside(c.x(), c.y()) && costmap.blocker(c.x(), c.y()) == Blocker::kObstacle)
      out.blocked_by_obstacle = true;
    return out;
  }
  out.path = withFinalApproach(costmap, footprint, r.path, goal, final_approach_m);
  out.ok = true;
  return out;
}

std::vector<Eigen::Vector2d> withFinalApproach(const Costmap& costmap, const Footprint& footprint,
                                               std::vector<Eigen::Vector2d> path, const Pose2D& goal, double length_m) {
  if (!(length_m > 0.0) || path.empty()) return path;
  const Eigen::Vector2d g(goal.x, goal.y), heading(std::cos(goal.yaw), std::sin(goal.yaw));
  const Eigen::Vector2d pre = g - length_m * heading;
  for (double d = 0.0; d <= length_m + 1e-9; d += 0.1) {
    const Eigen::Vector2d p = pre + d * heading;
    if (costmap.footprintBlocker({p.x(), p.y(), goal.yaw}, footprint) != Blocker::kNone) return path;
  }
  while (path.size() > 1 && (path.back() - g).norm() < length_m + 0.05) path.pop_back();
  if ((path.back() - g).norm() < length_m + 0.05) path.clear();
  path.push_back(pre);
  path.push_back(g);
  return path;
}

Approach approachAgain(const Costmap& costmap, const Footprint& footprint, const Pose2D& pose, const Pose2D& goal,
                       double final_approach_m, bool omnidirectional) {
  Approach a;
  const Eigen::Vector2d here(pose.x, pose.y), g(goal.x, goal.y);
  if (!omnidirectional && final_approach_m > 0.0) {
    const std::vector<Eigen::Vector2d> approach =
        withFinalApproach(costmap, footprint, {here, g}, goal, final_approach_m);
    if (approach.size() >= 2 && (approach.end()[-2] - g).norm() > 1e-3) {
      const Eigen::Vector2d pre = approach.end()[-2];
      a.first_leg = {here, pre};
      a.first_target = {pre.x(), pre.y(), goal.yaw};
      // Backwards when the approach's start lies behind the robot (it settled past it, facing the goal's way).
      a.reverse = (pre - here).dot(Eigen::Vector2d(std::cos(pose.yaw), std::sin(pose.yaw))) < 0.0;
      a.then_to_goal = true;
      return a;
    }
  }
  a.first_leg = {here, g};
  a.first_target = goal;
  return a;
}

std::string ArrivalParams::validate() const {
  if (!(xy_tolerance_m > 0.0) || !(yaw_tolerance_rad > 0.0)) return "xy and yaw tolerances must be > 0";
  if (max_corrections < 0) return "max_corrections must be >= 0";
  return {};
}

ArrivalJudgement ArrivalJudge::judge(const Pose2D& settled, const Pose2D& goal) {
  ArrivalJudgement j;
  if (!settled.finite() || !goal.finite()) {
    j.reason = "settled pose or goal is not finite";
    return j;
  }
  j.xy_err_m = std::hypot(settled.x - goal.x, settled.y - goal.y);
  j.yaw_err_rad = normalizeAngle(settled.yaw - goal.yaw);
  if (j.xy_err_m <= params_.xy_tolerance_m && std::abs(j.yaw_err_rad) <= params_.yaw_tolerance_rad) {
    j.verdict = ArrivalVerdict::kReached;
    return j;
  }
  if (corrections_ < params_.max_corrections) {
    ++corrections_;
    j.verdict = ArrivalVerdict::kApproachAgain;
    return j;
  }
  char buf[160];
  std::snprintf(buf, sizeof(buf), "settled %.3f m, %.3f rad off the goal after %d corrections", j.xy_err_m,
                j.yaw_err_rad, corrections_);
  j.reason = buf;
  return j;
}

}  // namespace thorvald_navigation
