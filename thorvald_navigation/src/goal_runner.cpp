#include "thorvald_navigation/goal_runner.h"

#include <cmath>
#include <utility>

#include "thorvald_common/format.h"

namespace thorvald_navigation {

namespace {

using thorvald_common::format;

void note(GoalTick* out, const std::string& text, bool warning = false) { out->notes.push_back({warning, text}); }

/// Keeps the notes gathered so far in `out` and replaces the rest by `next`.
void then(GoalTick next, GoalTick* out) {
  next.notes.insert(next.notes.begin(), out->notes.begin(), out->notes.end());
  next.new_plan = next.new_plan || out->new_plan;
  *out = std::move(next);
}

}  // namespace

std::string GoalRunnerParams::validate() const {
  if (const std::string e = follower.validate(); !e.empty()) return e;
  if (const std::string e = gate.validate(); !e.empty()) return e;
  if (!(planner_patience_s > 0.0)) return "planner_patience must be > 0 s";
  if (!(obstacle_wait_s > 0.0)) return "obstacle_wait must be > 0 s";
  if (!(settle_time_s >= 0.0)) return "settle_time must be >= 0 s";
  if (goal_corrections < 0) return "goal_corrections must be >= 0";
  if (!(replan_distance_m > 0.0)) return "replan_distance must be > 0 m";
  return "";
}

GoalPlanners costmapPlanners(std::function<const Costmap&()> costmap, const Footprint& footprint,
                             const PlannerParams& planner, double final_approach_m, double obstacle_check_ahead_m,
                             bool omnidirectional) {
  GoalPlanners p;
  p.plan = [=](const thorvald_base::Pose2D& start, const thorvald_base::Pose2D& goal) {
    GoalPlan r = planToGoal(costmap(), footprint, start, goal, planner, omnidirectional ? 0.0 : final_approach_m);
    r.first_target = goal;
    if (!r.ok || omnidirectional) return r;
    const PathDirection d = choosePathDirection(costmap(), footprint, start, r.path, goal, false);
    if (!d.ok) {  // driven forward as planned (the planner's circle clears it), with the reason on the log
      r.warning = d.error;
      return r;
    }
    r.path = d.approach.first_leg;
    r.reverse = d.approach.reverse;
    r.then_to_goal = d.approach.then_to_goal;
    r.first_target = d.approach.first_target;
    r.second_leg = d.approach.second_leg;
    return r;
  };
  p.approach_again = [=](const thorvald_base::Pose2D& pose, const thorvald_base::Pose2D& goal) {
    return approachAgain(costmap(), footprint, pose, goal, final_approach_m, omnidirectional);
  };
  p.obstacle_ahead = [=](const thorvald_base::Pose2D& pose, const std::vector<Eigen::Vector2d>& path,
                         std::size_t next_index, double goal_yaw, bool reversing) {
    return sweptObstacleDistance(costmap(), footprint, pose, path, next_index, obstacle_check_ahead_m, omnidirectional,
                                 goal_yaw, reversing) >= 0.0;
  };
  return p;
}

GoalRunner::GoalRunner(const GoalRunnerParams& params, GoalPlanners planners)
    : params_(params),
      planners_(std::move(planners)),
      follower_(params.follower),
      arrival_(
          ArrivalParams{params.follower.xy_tolerance_m, params.follower.yaw_tolerance_rad, params.goal_corrections}),
      gate_(params.gate) {}

GoalTick GoalRunner::accept(const thorvald_base::Pose2D& goal, double now_s) {
  if (!goal.finite()) return abort("goal pose is not finite (or its quaternion is zero)");
  goal_ = goal;
  active_ = true;
  need_plan_ = true;
  blocked_since_s_.reset();
  arrived_at_s_.reset();
  arrival_.reset();
  last_phase_ = FollowPhase::kIdle;
  to_pre_goal_ = false;
  holding_ = false;
  last_pose_.reset();
  started_s_ = now_s;
  GoalTick out;
  out.state = GoalState::kActive;
  note(&out, format("new goal (%.2f, %.2f, %.2f)", goal.x, goal.y, goal.yaw));
  return out;
}

GoalTick GoalRunner::cancel() {
  GoalTick out = stopped(GoalState::kCancelled);
  active_ = false;
  note(&out, "goal cancelled, robot stopped");
  return out;
}

GoalTick GoalRunner::abort(const std::string& reason) {
  GoalTick out = stopped(GoalState::kAborted);
  active_ = false;
  last_failure_ = reason;
  out.reason = reason;
  note(&out, "goal aborted: " + reason, true);
  return out;
}

GoalTick GoalRunner::stopped(GoalState state) {
  follower_.stop();
  GoalTick out;
  out.state = state;
  out.command = DriveCommand::kStop;
  return out;
}

GoalTick GoalRunner::tick(const GoalRunnerInput& in) {
  if (!active_) return GoalTick{};
  if (!in.pose) return noPose(in);
  const thorvald_base::Pose2D& pose = *in.pose;
  const double jump_m = last_pose_ ? std::hypot(pose.x - last_pose_->x, pose.y - last_pose_->y) : 0.0;
  last_pose_ = pose;
  if (jump_m > params_.replan_distance_m) {
    // The localiser moved the robot (a correction of a stale or aliased pose): the path and any arrival were
    // judged on the old pose. Stop for this cycle and plan again from the new one.
    GoalTick out = stopped();
    note(&out,
         format("the pose jumped %.2f m (relocalised): planning again from (%.3f, %.3f, %.3f)", jump_m, pose.x, pose.y,
                pose.yaw),
         true);
    to_pre_goal_ = false;
    next_leg_.clear();
    arrived_at_s_.reset();
    need_plan_ = true;
    return out;
  }
  GoalTick out;
  out.state = GoalState::kActive;
  const bool arriving = follower_.state() == FollowState::kArrived && !to_pre_goal_ && arrived_at_s_;
  if (!arriving && !mayDrive(in.now_s, &out)) return out;
  if (!planIfNeeded(pose, in.now_s, &out)) return out;
  if (planners_.obstacle_ahead(pose, path_, follower_.progressIndex() + 1, goal_.yaw, follower_.reversing())) {
    then(stopForObstacle(in.now_s), &out);
    return out;
  }
  blocked_since_s_.reset();
  const thorvald_base::Twist2D t = follower_.step(pose, in.dt_s);
  notePhase(pose, in.now_s, &out);
  if (follower_.state() == FollowState::kArrived) {
    then(arrived(pose, in.now_s), &out);
    return out;
  }
  out.command = DriveCommand::kTwist;
  out.twist = t;
  return out;
}

GoalTick GoalRunner::noPose(const GoalRunnerInput& in) {
  if (in.now_s - started_s_ > params_.planner_patience_s) return abort(in.no_pose_reason);
  return stopped();
}

bool GoalRunner::gateAllows(const GateVerdict& v, GoalTick* out) {
  if (v.action == GateAction::kAbort) {
    then(abort(v.reason), out);
    return false;
  }
  if (v.action == GateAction::kHold) {
    then(stopped(), out);
    if (!holding_) note(out, v.reason, true);
    holding_ = true;
    hold_reason_ = v.reason;
    return false;
  }
  return true;
}

bool GoalRunner::mayDrive(double now_s, GoalTick* out) {
  if (!gateAllows(gate_.whileDriving(now_s, started_s_), out)) return false;
  if (holding_) {  // relocalised: the pose may have moved, plan again from it
    holding_ = false;
    need_plan_ = true;
    ++counts_.relocalisation_waits;
    note(out, format("localiser %s again: replanning", localizerStateName(gate_.state())));
  }
  return true;
}

bool GoalRunner::planIfNeeded(const thorvald_base::Pose2D& pose, double now_s, GoalTick* out) {
  if (!need_plan_) return true;
  const GoalPlan r = planners_.plan(pose, goal_);
  if (!r.ok) {
    // A goal blocked by the map or keep-out is refused at once; one blocked by lidar obstacles waits.
    const bool obstacle = r.blocked_by_obstacle;
    if (!obstacle || !blocked_since_s_) blocked_since_s_ = now_s;
    if (!obstacle || now_s - *blocked_since_s_ > params_.obstacle_wait_s)
      then(abort(r.error), out);
    else
      then(stopped(), out);
    return false;
  }
  path_ = r.path;
  // A differential robot beside a wall may have to back along the path to its final approach's start.
  to_pre_goal_ = r.then_to_goal;
  pre_goal_ = Eigen::Vector2d(r.first_target.x, r.first_target.y);
  next_leg_ = r.second_leg;
  follower_.setPath(path_, r.then_to_goal ? r.first_target : goal_, r.reverse);
  if (r.reverse) note(out, "backing along the path: a turn forward would sweep the frame over the map");
  if (!r.warning.empty()) note(out, r.warning + "; driving the plan forward", true);
  out->new_plan = true;
  ++counts_.plans;
  need_plan_ = false;  // blocked_since_s_ stays: a new plan the obstacle still blocks does not restart the wait
  return true;
}

GoalTick GoalRunner::stopForObstacle(double now_s) {
  GoalTick out = stopped();
  if (!blocked_since_s_) {
    blocked_since_s_ = now_s;
    note(&out, "obstacle ahead: stopped, replanning", true);
  }
  ++counts_.obstacle_stops;
  need_plan_ = true;
  if (now_s - *blocked_since_s_ > params_.obstacle_wait_s)
    then(abort("path blocked by an obstacle for too long"), &out);
  return out;
}

void GoalRunner::notePhase(const thorvald_base::Pose2D& pose, double now_s, GoalTick* out) {
  if (follower_.phase() == last_phase_) return;
  last_phase_ = follower_.phase();
  note(out, format("%.2f s into the goal: %s%s at (%.3f, %.3f, %.3f), %.3f m from the goal", now_s - started_s_,
                   followPhaseName(last_phase_), follower_.reversing() ? " (reversing)" : "", pose.x, pose.y, pose.yaw,
                   std::hypot(pose.x - goal_.x, pose.y - goal_.y)));
}

GoalTick GoalRunner::arrived(const thorvald_base::Pose2D& pose, double now_s) {
  // The robot still moves a little after the last command (drive response, wheel slip while turning): judge the
  // pose once it stands, and approach again while it is outside the tolerances.
  if (to_pre_goal_) {  // at the start of the final approach: now straight to the goal
    to_pre_goal_ = false;
    path_ = next_leg_.empty() ? std::vector<Eigen::Vector2d>{pre_goal_, Eigen::Vector2d(goal_.x, goal_.y)} : next_leg_;
    next_leg_.clear();
    follower_.setPath(path_, goal_);
    GoalTick out;
    out.state = GoalState::kActive;
    return out;
  }
  GoalTick out = stopped();
  if (!arrived_at_s_) arrived_at_s_ = now_s;
  if (now_s - *arrived_at_s_ < params_.settle_time_s) return out;
  // Judged only on a pose the localiser stands by: wait while it is uncertain or lost, abort when that lasts.
  if (!gateAllows(gate_.atGoal(now_s, started_s_, *arrived_at_s_ + params_.settle_time_s), &out)) return out;
  if (holding_) {
    holding_ = false;
    ++counts_.relocalisation_waits;
    note(&out, format("localiser %s again at the goal", localizerStateName(gate_.state())));
  }
  arrived_at_s_.reset();
  then(judgeArrival(pose, now_s), &out);
  return out;
}

GoalTick GoalRunner::judgeArrival(const thorvald_base::Pose2D& pose, double now_s) {
  const ArrivalJudgement j = arrival_.judge(pose, goal_);
  GoalTick out = stopped();
  if (j.verdict == ArrivalVerdict::kApproachAgain && j.xy_err_m <= params_.follower.xy_tolerance_m) {
    // Only the heading is off: turn again where the robot stands (backing off would cost the position).
    note(&out, format("settled %.3f m, %.3f rad off the goal: turning again (%d of %d)", j.xy_err_m, j.yaw_err_rad,
                      arrival_.corrections(), params_.goal_corrections));
    follower_.turnTo(goal_);
    to_pre_goal_ = false;
    return out;
  }
  if (j.verdict == ArrivalVerdict::kApproachAgain && j.xy_err_m > params_.replan_distance_m) {
    // Far from the goal: the pose the plan was made on was wrong. A straight renewed approach from here was never
    // checked against the map (it backed a robot sideways into a side wall); plan the whole way again.
    note(&out, format("settled %.3f m, %.3f rad off the goal: planning again from here (%d of %d)", j.xy_err_m,
                      j.yaw_err_rad, arrival_.corrections(), params_.goal_corrections));
    to_pre_goal_ = false;
    next_leg_.clear();
    need_plan_ = true;
    return out;
  }
  if (j.verdict == ArrivalVerdict::kApproachAgain) {
    const Approach a = planners_.approach_again(pose, goal_);
    note(&out,
         format("settled %.3f m, %.3f rad off the goal: approaching again%s (%d of %d)", j.xy_err_m, j.yaw_err_rad,
                a.reverse ? ", backing off first" : "", arrival_.corrections(), params_.goal_corrections));
    path_ = a.first_leg;
    follower_.setPath(path_, a.first_target, a.reverse);
    to_pre_goal_ = a.then_to_goal;
    pre_goal_ = Eigen::Vector2d(a.first_target.x, a.first_target.y);
    next_leg_ = a.second_leg;
    return out;
  }
  active_ = false;
  if (j.verdict == ArrivalVerdict::kFailed) return abort(j.reason);
  note(&out, format("goal reached (%.3f m, %.3f rad off, %d corrections) after %.1f s", j.xy_err_m, j.yaw_err_rad,
                    arrival_.corrections(), now_s - started_s_));
  out.state = GoalState::kSucceeded;
  ++counts_.reached;
  return out;
}

}  // namespace thorvald_navigation
