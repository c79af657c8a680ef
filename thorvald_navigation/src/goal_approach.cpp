#include "thorvald_navigation/goal_approach.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

namespace thorvald_navigation {

GoalPlan planToGoal(const Costmap& costmap, const Footprint& footprint, const thorvald_base::Pose2D& start,
                    const thorvald_base::Pose2D& goal, const PlannerParams& planner, double final_approach_m) {
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
                                               std::vector<Eigen::Vector2d> path, const thorvald_base::Pose2D& goal,
                                               double length_m) {
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

Approach approachAgain(const Costmap& costmap, const Footprint& footprint, const thorvald_base::Pose2D& pose,
                       const thorvald_base::Pose2D& goal, double final_approach_m, bool omnidirectional) {
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

namespace {

/// Sweeps the footprint along a differential robot's motion (turns on the spot and straight legs) and names the first
/// wall, keep-out zone or unknown space it meets. A blocker the footprint overlaps where the robot stands is not held
/// against it until the footprint has once been clear of it (a robot pushed against a wall may still get away).
class MotionSweep {
 public:
  MotionSweep(const Costmap& costmap, const Footprint& footprint, const thorvald_base::Pose2D& start)
      : costmap_(costmap), footprint_(footprint), step_(std::max(0.05, costmap.geometry().resolution_m)) {
    for (std::size_t i = 0; i < kKinds.size(); ++i) standing_[i] = costmap.footprintCells(start, footprint, kKinds[i]);
  }
  /// Turning on the spot at `p` from `from` to `to` [rad].
  Blocker turn(const Eigen::Vector2d& p, double from, double to) {
    for (std::size_t i = 0; i < kKinds.size(); ++i)
      if (turnTouches(costmap_, footprint_, p, from, to, kKinds[i], step_, &standing_[i])) return kKinds[i];
    return at({p.x(), p.y(), to});
  }
  /// Driving straight from `a` to `b` with the heading `yaw` [rad].
  Blocker move(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double yaw) {
    const double length = (b - a).norm();
    const int n = static_cast<int>(std::ceil(length / step_));
    for (int k = 1; k <= n; ++k) {
      const Eigen::Vector2d p = a + (b - a) * (static_cast<double>(k) / n);
      if (const Blocker hit = at({p.x(), p.y(), yaw}); hit != Blocker::kNone) return hit;
    }
    return Blocker::kNone;
  }

 private:
  // The cells the start pose's footprint already stands on are not held against a motion (the robot is there) until
  // the footprint has left them all; any other blocked cell is: a turn that sweeps the frame further into a wall it
  // touches is refused.
  Blocker at(const thorvald_base::Pose2D& pose) {
    for (std::size_t i = 0; i < kKinds.size(); ++i) {
      if (costmap_.footprintTouches(pose, footprint_, kKinds[i], &standing_[i])) return kKinds[i];
      if (!standing_[i].empty() && !costmap_.footprintTouches(pose, footprint_, kKinds[i])) standing_[i].clear();
    }
    return Blocker::kNone;
  }

  static constexpr std::array<Blocker, 3> kKinds{Blocker::kWall, Blocker::kKeepOut, Blocker::kUnknown};
  const Costmap& costmap_;
  const Footprint& footprint_;
  double step_;
  std::array<std::vector<int>, 3> standing_;
};

/// The first motion on `legs` (driven backwards when `reverse`) that sweeps the footprint over a wall, the keep-out
/// zone or unknown space, as text; empty when all clear. The robot turns on the spot at the start, from its heading to
/// the way to the first point 0.3 m along (the follower turns on the spot when far off its path), at every corner of
/// the path's points taken 0.3 m apart from one leg's way to the next, and at the end to `end_yaw`; between them it
/// drives the legs straight with the oriented footprint. (The follower cuts a gentle corner with an arc inside that
/// turn.)
std::string firstBlockedMotion(const Costmap& costmap, const Footprint& footprint, const thorvald_base::Pose2D& start,
                               const std::vector<Eigen::Vector2d>& legs, double end_yaw, bool reverse) {
  constexpr double kChord = 0.3;
  const auto way = [reverse](const Eigen::Vector2d& from, const Eigen::Vector2d& to) {
    const Eigen::Vector2d d = to - from;
    return thorvald_base::normalizeAngle(std::atan2(d.y(), d.x()) + (reverse ? thorvald_base::kPi : 0.0));
  };
  const auto describe = [](const char* which, const Eigen::Vector2d& p, double from, double to, Blocker b) {
    char text[128];
    std::snprintf(text, sizeof(text), "the %s at (%.2f, %.2f) from %.2f to %.2f rad sweeps over ", which, p.x(), p.y(),
                  from, to);
    return std::string(text) + blockerName(b);
  };
  // The ways the robot heads along: the path's points at least 0.3 m apart (the planner's short grid steps and the
  // corners it cut are driven as one leg, not turned into one by one), always with its first and last point.
  std::vector<Eigen::Vector2d> driven{legs.front()};
  for (std::size_t i = 1; i < legs.size(); ++i) {
    const bool last = i + 1 == legs.size();
    if ((legs[i] - driven.back()).norm() >= kChord) {
      driven.push_back(legs[i]);
    } else if (last) {
      if (driven.size() > 1) driven.pop_back();
      driven.push_back(legs[i]);
    }
  }
  MotionSweep sweep(costmap, footprint, start);
  double heading = start.yaw;
  Blocker b = Blocker::kNone;
  for (std::size_t i = 0; i + 1 < driven.size(); ++i) {
    if ((driven[i + 1] - driven[i]).norm() < 1e-6) continue;
    const double w = way(driven[i], driven[i + 1]);
    if (std::abs(thorvald_base::normalizeAngle(w - heading)) > 1e-3) {
      b = sweep.turn(driven[i], heading, w);
      if (b != Blocker::kNone) return describe(i == 0 ? "first turn" : "turn", driven[i], heading, w, b);
      heading = w;
    }
    b = sweep.move(driven[i], driven[i + 1], heading);
    if (b != Blocker::kNone) {
      char text[128];
      std::snprintf(text, sizeof(text), "the way from (%.2f, %.2f) to (%.2f, %.2f) runs the frame over ", driven[i].x(),
                    driven[i].y(), driven[i + 1].x(), driven[i + 1].y());
      return text + std::string(blockerName(b));
    }
  }
  b = sweep.turn(legs.back(), heading, end_yaw);
  if (b != Blocker::kNone) return describe("final turn", legs.back(), heading, end_yaw, b);
  return {};
}

/// The way from `path[k]` to its first point at least 0.3 m on (or the last) [rad].
double wayOn(const std::vector<Eigen::Vector2d>& path, std::size_t k) {
  std::size_t a = k + 1;
  while (a + 1 < path.size() && (path[a] - path[k]).norm() < 0.3) ++a;
  const Eigen::Vector2d d = path[a] - path[k];
  return std::atan2(d.y(), d.x());
}

/// Backwards along `path` to the first of its points (every 0.1 m) where the robot can turn to the way on and drive the
/// rest forward, every motion clear; false when there is none.
bool splitPath(const Costmap& costmap, const Footprint& footprint, const thorvald_base::Pose2D& start,
               const std::vector<Eigen::Vector2d>& path, const thorvald_base::Pose2D& goal, Approach* out) {
  std::vector<Eigen::Vector2d> dense{path.front()};
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const int n = std::max(1, static_cast<int>(std::ceil((path[i + 1] - path[i]).norm() / 0.1)));
    for (int k = 1; k <= n; ++k) dense.push_back(path[i] + (path[i + 1] - path[i]) * (static_cast<double>(k) / n));
  }
  for (std::size_t k = 1; k + 1 < dense.size(); ++k) {
    const double on = wayOn(dense, k);
    const std::vector<Eigen::Vector2d> back(dense.begin(), dense.begin() + static_cast<long>(k) + 1);
    if (!firstBlockedMotion(costmap, footprint, start, back, on, true).empty()) continue;
    const thorvald_base::Pose2D turn_at{dense[k].x(), dense[k].y(), on};
    const std::vector<Eigen::Vector2d> ahead(dense.begin() + static_cast<long>(k), dense.end());
    if (!firstBlockedMotion(costmap, footprint, turn_at, ahead, goal.yaw, false).empty()) continue;
    out->first_leg = back;
    out->first_target = turn_at;
    out->reverse = true;
    out->then_to_goal = true;
    out->second_leg = ahead;
    return true;
  }
  return false;
}

}  // namespace

PathDirection choosePathDirection(const Costmap& costmap, const Footprint& footprint,
                                  const thorvald_base::Pose2D& start, const std::vector<Eigen::Vector2d>& path,
                                  const thorvald_base::Pose2D& goal, bool omnidirectional) {
  PathDirection out;
  out.approach.first_leg = path;
  out.approach.first_target = goal;
  if (omnidirectional || path.size() < 2) return out;
  const std::string forward = firstBlockedMotion(costmap, footprint, start, path, goal.yaw, false);
  if (forward.empty()) return out;
  // Backwards as far as the final approach's start (the path's last segment runs along the goal's heading when it
  // has one), then forward along it: the robot then never turns its rear through the goal's side.
  std::vector<Eigen::Vector2d> back = path;
  const Eigen::Vector2d heading(std::cos(goal.yaw), std::sin(goal.yaw));
  const Eigen::Vector2d last = path.end()[-1] - path.end()[-2];
  const bool has_final_approach =
      path.size() >= 3 && last.norm() > 1e-3 && std::abs(last.normalized().dot(heading) - 1.0) < 1e-6;
  if (has_final_approach) back.pop_back();
  const thorvald_base::Pose2D target =
      has_final_approach ? thorvald_base::Pose2D{back.back().x(), back.back().y(), goal.yaw} : goal;
  std::string backward = firstBlockedMotion(costmap, footprint, start, back, target.yaw, true);
  if (backward.empty() && has_final_approach) {
    // The last stretch forward along the goal's heading needs no turn.
    out.approach.first_leg = back;
    out.approach.first_target = target;
    out.approach.reverse = true;
    out.approach.then_to_goal = true;
    return out;
  }
  if (backward.empty()) {
    out.approach.reverse = true;
    return out;
  }
  if (splitPath(costmap, footprint, start, path, goal, &out.approach)) return out;
  out.ok = false;
  out.error = "no way to drive the path without sweeping the robot over the map: forward, " + forward +
              "; backwards, " + backward;
  return out;
}

std::string ArrivalParams::validate() const {
  if (!(xy_tolerance_m > 0.0) || !(yaw_tolerance_rad > 0.0)) return "xy and yaw tolerances must be > 0";
  if (max_corrections < 0) return "max_corrections must be >= 0";
  return {};
}

ArrivalJudgement ArrivalJudge::judge(const thorvald_base::Pose2D& settled, const thorvald_base::Pose2D& goal) {
  ArrivalJudgement j;
  if (!settled.finite() || !goal.finite()) {
    j.reason = "settled pose or goal is not finite";
    return j;
  }
  j.xy_err_m = std::hypot(settled.x - goal.x, settled.y - goal.y);
  j.yaw_err_rad = thorvald_base::normalizeAngle(settled.yaw - goal.yaw);
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
