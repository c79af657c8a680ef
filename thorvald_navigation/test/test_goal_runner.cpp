// GoalRunner without ROS: a kinematic robot executes its commands at 20 Hz, fake planners stand in for the costmap.
#include <cmath>
#include <functional>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "thorvald_base/angles.h"
#include "thorvald_navigation/goal_runner.h"

namespace tn = thorvald_navigation;
using thorvald_base::Pose2D;
using tn::DriveCommand;
using tn::GoalState;

namespace {

constexpr double kDt = 0.05;

bool hasNote(const tn::GoalTick& t, const std::string& part) {
  for (const auto& n : t.notes)
    if (n.text.find(part) != std::string::npos) return true;
  return false;
}

double distance(const Pose2D& a, const Pose2D& b) { return std::hypot(a.x - b.x, a.y - b.y); }

// A differential robot that does exactly what it is told, the runner and fake planners whose answers the tests set.
struct Bench {
  tn::GoalRunnerParams params;
  Pose2D pose{0.0, 0.0, 0.0};
  double now_s = 100.0;
  bool plan_fails = false, plan_blocked_by_obstacle = false, obstacle = false;
  int plans_asked = 0, approaches_asked = 0;
  Pose2D last_plan_start;
  std::function<tn::Approach(const Pose2D&, const Pose2D&)> approach;  // empty: straight to the goal
  std::unique_ptr<tn::GoalRunner> runner;
  tn::GoalTick last;

  explicit Bench(const std::function<void(tn::GoalRunnerParams&)>& tune = {}) {
    params.follower.command_latency_s = 0.0;  // the kinematic robot responds at once
    if (tune) tune(params);
    EXPECT_EQ(params.validate(), "");
    runner = std::make_unique<tn::GoalRunner>(params, planners());
  }

  tn::GoalPlanners planners() {
    tn::GoalPlanners p;
    p.plan = [this](const Pose2D& start, const Pose2D& goal) {
      ++plans_asked;
      last_plan_start = start;
      tn::GoalPlan r;
      r.ok = !plan_fails;
      r.blocked_by_obstacle = plan_fails && plan_blocked_by_obstacle;
      r.error =
          plan_fails ? (plan_blocked_by_obstacle ? "goal blocked by an obstacle" : "goal on the keep-out zone") : "";
      if (r.ok) r.path = {{start.x, start.y}, {goal.x, goal.y}};
      return r;
    };
    p.approach_again = [this](const Pose2D& from, const Pose2D& goal) {
      ++approaches_asked;
      if (approach) return approach(from, goal);
      tn::Approach a;
      a.first_leg = {{from.x, from.y}, {goal.x, goal.y}};
      a.first_target = goal;
      return a;
    };
    p.obstacle_ahead = [this](const Pose2D&, const std::vector<Eigen::Vector2d>&, std::size_t, double, bool) {
      return obstacle;
    };
    return p;
  }

  // One control cycle: the runner's command is executed for kDt.
  const tn::GoalTick& step() {
    tn::GoalRunnerInput in;
    in.now_s = now_s;
    in.pose = pose;
    in.dt_s = kDt;
    last = runner->tick(in);
    if (last.command == DriveCommand::kTwist) {
      const double c = std::cos(pose.yaw), s = std::sin(pose.yaw);
      pose.x += (c * last.twist.vx - s * last.twist.vy) * kDt;
      pose.y += (s * last.twist.vx + c * last.twist.vy) * kDt;
      pose.yaw = thorvald_base::normalizeAngle(pose.yaw + last.twist.wz * kDt);
    }
    now_s += kDt;
    return last;
  }

  // Steps until `done` (true) or `seconds` have passed (false); `each` sees every cycle's outcome.
  bool runUntil(const std::function<bool()>& done, double seconds,
                const std::function<void(const tn::GoalTick&)>& each = {}) {
    for (int i = 0; i < static_cast<int>(seconds / kDt); ++i) {
      step();
      if (each) each(last);
      if (done()) return true;
    }
    return false;
  }
  bool finished() const { return last.state != GoalState::kActive; }
  // Steps until the follower reports its arrival: the first zero command.
  bool runToArrival(double seconds) {
    return runUntil([this] { return last.command == DriveCommand::kStop || finished(); }, seconds);
  }
};

TEST(GoalRunner, ReachesAGoalOnAStraightPathAndSucceedsOnce) {
  Bench b;
  const Pose2D goal{3.0, 0.5, 0.4};
  const tn::GoalTick accepted = b.runner->accept(goal, b.now_s);
  EXPECT_EQ(accepted.state, GoalState::kActive);
  EXPECT_TRUE(hasNote(accepted, "new goal (3.00, 0.50, 0.40)"));
  int plans_published = 0, twists = 0;
  ASSERT_TRUE(b.runUntil([&] { return b.finished(); }, 60.0,
                         [&](const tn::GoalTick& t) {
                           plans_published += t.new_plan;
                           twists += t.command == DriveCommand::kTwist;
                         }));
  EXPECT_EQ(b.last.state, GoalState::kSucceeded) << b.last.reason;
  EXPECT_EQ(b.last.command, DriveCommand::kStop);
  EXPECT_TRUE(hasNote(b.last, "goal reached")) << b.last.notes.size();
  EXPECT_LT(distance(b.pose, goal), b.params.follower.xy_tolerance_m);
  EXPECT_LT(std::abs(thorvald_base::normalizeAngle(b.pose.yaw - goal.yaw)), b.params.follower.yaw_tolerance_rad);
  EXPECT_EQ(plans_published, 1);
  EXPECT_GT(twists, 50);
  EXPECT_EQ(b.plans_asked, 1);
  EXPECT_EQ(b.approaches_asked, 0);
  EXPECT_EQ(b.runner->counts().reached, 1);
  EXPECT_FALSE(b.runner->active());
  // Finished: nothing more is sent.
  b.step();
  EXPECT_EQ(b.last.state, GoalState::kIdle);
  EXPECT_EQ(b.last.command, DriveCommand::kNone);
}

// The pose is judged only after the robot stood settle_time: no result before it, zero commands meanwhile.
TEST(GoalRunner, JudgesThePoseOnlyAfterSettling) {
  Bench b([](tn::GoalRunnerParams& p) { p.settle_time_s = 1.0; });
  b.runner->accept({2.0, 0.0, 0.0}, b.now_s);
  ASSERT_TRUE(b.runToArrival(30.0));
  const double arrived_s = b.now_s - kDt;
  ASSERT_EQ(b.last.state, GoalState::kActive);
  ASSERT_TRUE(b.runUntil([&] { return b.finished(); }, 5.0,
                         [](const tn::GoalTick& t) { EXPECT_EQ(t.command, DriveCommand::kStop); }));
  EXPECT_EQ(b.last.state, GoalState::kSucceeded);
  EXPECT_GE(b.now_s - kDt - arrived_s, 1.0 - 1e-9);
  EXPECT_LT(b.now_s - kDt - arrived_s, 1.0 + 2 * kDt);
}

// The robot slides 5 cm after stopping: the settled pose is outside the tolerance, it approaches again and succeeds
// with one correction.
TEST(GoalRunner, ApproachesAgainWhenTheSettledPoseIsOff) {
  Bench b;
  const Pose2D goal{2.0, 0.0, 0.0};
  b.runner->accept(goal, b.now_s);
  ASSERT_TRUE(b.runToArrival(30.0));
  b.pose.x += 0.05;
  ASSERT_TRUE(b.runUntil([&] { return b.approaches_asked > 0; }, 2.0));
  EXPECT_TRUE(hasNote(b.last, "approaching again (1 of 3)"));
  EXPECT_EQ(b.runner->path().back(), Eigen::Vector2d(2.0, 0.0));
  ASSERT_TRUE(b.runUntil([&] { return b.finished(); }, 60.0));
  EXPECT_EQ(b.last.state, GoalState::kSucceeded) << b.last.reason;
  EXPECT_TRUE(hasNote(b.last, "1 corrections"));
  EXPECT_EQ(b.plans_asked, 1);  // a correction is no new plan
  EXPECT_LT(distance(b.pose, goal), b.params.follower.xy_tolerance_m);
}

// The pose moves 1.6 m in steps below replan_distance as the robot stands at the goal (the localiser corrects a
// stale pose over a few cycles): the settled pose is planned from again, not approached straight (that way was never
// checked against the map), and the goal reached.
TEST(GoalRunner, AFarOffSettledPoseIsPlannedFromAgain) {
  Bench b;
  const Pose2D goal{2.0, 0.0, 0.0};
  b.runner->accept(goal, b.now_s);
  ASSERT_TRUE(b.runToArrival(30.0));
  EXPECT_EQ(b.plans_asked, 1);
  for (int i = 0; i < 4; ++i) {
    b.pose.y += 0.4;
    b.step();
    EXPECT_FALSE(hasNote(b.last, "the pose jumped"));
  }
  ASSERT_TRUE(b.runUntil([&] { return hasNote(b.last, "planning again from here (1 of 3)"); }, 2.0));
  ASSERT_TRUE(b.runUntil([&] { return b.finished(); }, 60.0));
  EXPECT_EQ(b.last.state, GoalState::kSucceeded) << b.last.reason;
  EXPECT_EQ(b.approaches_asked, 0);
  EXPECT_EQ(b.plans_asked, 2);
  EXPECT_NEAR(b.last_plan_start.y, 1.6, 1e-6);
  EXPECT_LT(distance(b.pose, goal), b.params.follower.xy_tolerance_m);
}

// The pose jumps 1 m sideways while the robot drives (the localiser corrects it): the robot stops and plans again
// from the new pose, and reaches the goal.
TEST(GoalRunner, APoseJumpWhileDrivingIsPlannedFromAgain) {
  Bench b;
  const Pose2D goal{3.0, 0.0, 0.0};
  b.runner->accept(goal, b.now_s);
  ASSERT_TRUE(b.runUntil([&] { return b.pose.x > 1.0; }, 30.0));
  EXPECT_EQ(b.plans_asked, 1);
  b.pose.y += 1.0;
  b.step();
  EXPECT_TRUE(hasNote(b.last, "the pose jumped 1.00 m")) << (b.last.notes.empty() ? "" : b.last.notes[0].text);
  EXPECT_EQ(b.last.command, DriveCommand::kStop);
  ASSERT_TRUE(b.runUntil([&] { return b.finished(); }, 60.0));
  EXPECT_EQ(b.last.state, GoalState::kSucceeded) << b.last.reason;
  EXPECT_EQ(b.plans_asked, 2);
  EXPECT_NEAR(b.last_plan_start.y, 1.0, 1e-6);
  EXPECT_LT(distance(b.pose, goal), b.params.follower.xy_tolerance_m);
}

// Only the heading is off: the robot turns again where it stands, with no new approach.
TEST(GoalRunner, TurnsAgainWhenOnlyTheHeadingIsOff) {
  Bench b;
  b.runner->accept({2.0, 0.0, 0.0}, b.now_s);
  ASSERT_TRUE(b.runToArrival(30.0));
  b.pose.yaw += 0.05;
  const Pose2D off = b.pose;
  ASSERT_TRUE(b.runUntil([&] { return hasNote(b.last, "turning again"); }, 2.0));
  ASSERT_TRUE(b.runUntil([&] { return b.finished(); }, 30.0));
  EXPECT_EQ(b.last.state, GoalState::kSucceeded) << b.last.reason;
  EXPECT_EQ(b.approaches_asked, 0);
  EXPECT_LT(distance(b.pose, off), 1e-6);  // turned on the spot
  EXPECT_LT(std::abs(b.pose.yaw), b.params.follower.yaw_tolerance_rad);
}

// A correction in two legs (back off to the final approach's start, then to the goal): between them one cycle
// without a command, then the second leg straight from there to the goal.
TEST(GoalRunner, ACorrectionInTwoLegsDrivesTheSecondOnceTheFirstIsDone) {
  Bench b;
  const Pose2D goal{2.0, 0.0, 0.0};
  b.approach = [](const Pose2D& from, const Pose2D&) {
    tn::Approach a;
    a.first_target = {1.7, 0.0, 0.0};
    a.first_leg = {{from.x, from.y}, {1.7, 0.0}};
    a.reverse = true;
    a.then_to_goal = true;
    return a;
  };
  b.runner->accept(goal, b.now_s);
  ASSERT_TRUE(b.runToArrival(30.0));
  b.pose.y += 0.05;
  ASSERT_TRUE(b.runUntil([&] { return b.approaches_asked > 0; }, 2.0));
  ASSERT_TRUE(b.runUntil([&] { return b.last.command == DriveCommand::kNone; }, 30.0));
  ASSERT_EQ(b.runner->path().size(), 2u);
  EXPECT_EQ(b.runner->path().front(), Eigen::Vector2d(1.7, 0.0));
  EXPECT_EQ(b.runner->path().back(), Eigen::Vector2d(2.0, 0.0));
  ASSERT_TRUE(b.runUntil([&] { return b.finished(); }, 60.0));
  EXPECT_EQ(b.last.state, GoalState::kSucceeded) << b.last.reason;
}

// Every settled pose is off: after goal_corrections approaches the goal fails with the remaining error.
TEST(GoalRunner, AbortsWhenTheCorrectionsRunOut) {
  Bench b([](tn::GoalRunnerParams& p) { p.goal_corrections = 2; });
  b.runner->accept({2.0, 0.0, 0.0}, b.now_s);
  bool was_stopped = false;
  ASSERT_TRUE(b.runUntil([&] { return b.finished(); }, 120.0,
                         [&](const tn::GoalTick& t) {
                           if (t.command == DriveCommand::kStop && !was_stopped)
                             b.pose.x += 0.05;  // slides after every stop
                           was_stopped = t.command == DriveCommand::kStop;
                         }));
  EXPECT_EQ(b.last.state, GoalState::kAborted);
  EXPECT_EQ(b.approaches_asked, 2);
  EXPECT_FALSE(b.last.reason.empty());
  EXPECT_EQ(b.runner->lastFailure(), b.last.reason);
}

// A new goal replaces the current one: planned from where the robot is, the old one never reported.
TEST(GoalRunner, ANewGoalPreemptsTheCurrentOne) {
  Bench b;
  b.runner->accept({4.0, 0.0, 0.0}, b.now_s);
  ASSERT_TRUE(b.runUntil([&] { return b.pose.x > 1.0; }, 30.0));
  const Pose2D at = b.pose;
  const Pose2D second{1.0, 1.0, 1.57};
  EXPECT_EQ(b.runner->accept(second, b.now_s).state, GoalState::kActive);
  b.step();
  EXPECT_EQ(b.plans_asked, 2);
  EXPECT_LT(distance(b.last_plan_start, at), 1e-9);
  EXPECT_EQ(b.runner->goal().yaw, 1.57);
  ASSERT_TRUE(b.runUntil([&] { return b.finished(); }, 60.0));
  EXPECT_EQ(b.last.state, GoalState::kSucceeded);
  EXPECT_LT(distance(b.pose, second), b.params.follower.xy_tolerance_m);
  EXPECT_EQ(b.runner->counts().reached, 1);
}

TEST(GoalRunner, CancelStopsTheRobotAndEndsTheGoal) {
  Bench b;
  b.runner->accept({4.0, 0.0, 0.0}, b.now_s);
  ASSERT_TRUE(b.runUntil([&] { return b.pose.x > 1.0; }, 30.0));
  const tn::GoalTick c = b.runner->cancel();
  EXPECT_EQ(c.state, GoalState::kCancelled);
  EXPECT_EQ(c.command, DriveCommand::kStop);
  EXPECT_FALSE(b.runner->active());
  const Pose2D at = b.pose;
  b.runUntil([] { return false; }, 1.0);
  EXPECT_EQ(b.last.command, DriveCommand::kNone);
  EXPECT_EQ(b.last.state, GoalState::kIdle);
  EXPECT_EQ(distance(b.pose, at), 0.0);
}

TEST(GoalRunner, AGoalTheMapRefusesIsAbortedAtOnceWithThePlannersReason) {
  Bench b;
  b.plan_fails = true;
  b.runner->accept({2.0, 0.0, 0.0}, b.now_s);
  b.step();
  EXPECT_EQ(b.last.state, GoalState::kAborted);
  EXPECT_EQ(b.last.command, DriveCommand::kStop);
  EXPECT_EQ(b.last.reason, "goal on the keep-out zone");
  EXPECT_TRUE(hasNote(b.last, "goal aborted: goal on the keep-out zone"));
  EXPECT_EQ(b.plans_asked, 1);
}

TEST(GoalRunner, ANonFiniteGoalIsAbortedAtOnce) {
  Bench b;
  const tn::GoalTick t = b.runner->accept({std::nan(""), 0.0, 0.0}, b.now_s);
  EXPECT_EQ(t.state, GoalState::kAborted);
  EXPECT_NE(t.reason.find("not finite"), std::string::npos);
  EXPECT_FALSE(b.runner->active());
}

// Lidar obstacles on the goal: the robot stands and the planner is asked again every cycle; it drives as soon as a
// plan comes, and gives up after obstacle_wait when none does.
TEST(GoalRunner, AGoalBlockedByObstaclesWaitsForThemThenAborts) {
  Bench b([](tn::GoalRunnerParams& p) { p.obstacle_wait_s = 2.0; });
  b.plan_fails = b.plan_blocked_by_obstacle = true;
  b.runner->accept({2.0, 0.0, 0.0}, b.now_s);
  ASSERT_FALSE(b.runUntil([&] { return b.finished(); }, 1.0));
  EXPECT_EQ(b.last.command, DriveCommand::kStop);
  EXPECT_GE(b.plans_asked, 19);
  EXPECT_TRUE(b.runner->blocked());
  b.plan_fails = false;  // the person walked off
  b.step();
  EXPECT_TRUE(b.last.new_plan);
  EXPECT_EQ(b.last.command, DriveCommand::kTwist);
  EXPECT_FALSE(b.runner->blocked());

  Bench c([](tn::GoalRunnerParams& p) { p.obstacle_wait_s = 2.0; });
  c.plan_fails = c.plan_blocked_by_obstacle = true;
  const double start_s = c.now_s;
  c.runner->accept({2.0, 0.0, 0.0}, c.now_s);
  ASSERT_TRUE(c.runUntil([&] { return c.finished(); }, 5.0));
  EXPECT_EQ(c.last.state, GoalState::kAborted);
  EXPECT_EQ(c.last.reason, "goal blocked by an obstacle");
  EXPECT_GT(c.now_s - kDt - start_s, 2.0);
  EXPECT_LT(c.now_s - kDt - start_s, 2.0 + 2 * kDt);
}

// An obstacle on the path ahead: stop, replan every cycle while it stays, go on when it leaves, give up when it
// stays for obstacle_wait.
TEST(GoalRunner, AnObstacleAheadStopsTheRobotReplansAndAbortsWhenItStays) {
  Bench b([](tn::GoalRunnerParams& p) { p.obstacle_wait_s = 2.0; });
  b.runner->accept({4.0, 0.0, 0.0}, b.now_s);
  ASSERT_TRUE(b.runUntil([&] { return b.pose.x > 1.0; }, 30.0));
  b.obstacle = true;
  b.step();
  EXPECT_EQ(b.last.command, DriveCommand::kStop);
  EXPECT_TRUE(hasNote(b.last, "obstacle ahead: stopped, replanning"));
  const Pose2D stopped_at = b.pose;
  const int plans = b.plans_asked;
  b.runUntil([] { return false; }, 1.0);
  EXPECT_EQ(distance(b.pose, stopped_at), 0.0);
  EXPECT_EQ(b.plans_asked, plans + 20);
  EXPECT_EQ(b.runner->counts().obstacle_stops, 21);
  EXPECT_TRUE(b.runner->blocked());
  b.obstacle = false;
  b.step();
  EXPECT_EQ(b.last.command, DriveCommand::kTwist);
  EXPECT_FALSE(b.runner->blocked());

  b.obstacle = true;
  const double blocked_s = b.now_s;
  ASSERT_TRUE(b.runUntil([&] { return b.finished(); }, 5.0));
  EXPECT_EQ(b.last.state, GoalState::kAborted);
  EXPECT_EQ(b.last.reason, "path blocked by an obstacle for too long");
  EXPECT_GT(b.now_s - kDt - blocked_s, 2.0);
}

// No pose (no map, no transform): the robot is stopped, and the goal aborted with the caller's reason after
// planner_patience.
TEST(GoalRunner, WithoutAPoseTheRobotStopsAndTheGoalIsAbortedAfterThePlannersPatience) {
  Bench b;
  b.runner->accept({2.0, 0.0, 0.0}, b.now_s);
  tn::GoalRunnerInput in;
  in.no_pose_reason = "no map received on 'map'";
  in.now_s = b.now_s + 4.9;
  tn::GoalTick t = b.runner->tick(in);
  EXPECT_EQ(t.state, GoalState::kActive);
  EXPECT_EQ(t.command, DriveCommand::kStop);
  in.now_s = b.now_s + 5.1;
  t = b.runner->tick(in);
  EXPECT_EQ(t.state, GoalState::kAborted);
  EXPECT_EQ(t.reason, "no map received on 'map'");
  EXPECT_EQ(b.plans_asked, 0);
}

// A lost localiser holds the robot where it stands; relocalised, it replans from its pose and reaches the goal.
TEST(GoalRunner, ALostLocaliserHoldsTheRobotStillAndItReplansWhenRelocalised) {
  Bench b;
  const Pose2D goal{4.0, 0.0, 0.0};
  b.runner->accept(goal, b.now_s);
  ASSERT_TRUE(b.runUntil([&] { return b.pose.x > 1.0; }, 30.0));
  b.runner->setLocalizerStatus(tn::LocalizerState::kLost, b.now_s);
  b.step();
  EXPECT_EQ(b.last.command, DriveCommand::kStop);
  EXPECT_TRUE(hasNote(b.last, "localiser lost: stopped"));
  const Pose2D held = b.pose;
  int warnings = 0;
  b.runUntil([] { return false; }, 3.0,
             [&](const tn::GoalTick& t) {
               EXPECT_EQ(t.command, DriveCommand::kStop);
               warnings += static_cast<int>(t.notes.size());
             });
  EXPECT_EQ(warnings, 0);  // said once
  EXPECT_EQ(distance(b.pose, held), 0.0);
  EXPECT_TRUE(b.runner->holding());
  EXPECT_NE(b.runner->holdReason().find("waiting for relocalisation"), std::string::npos);
  b.runner->setLocalizerStatus(tn::LocalizerState::kUncertain, b.now_s);
  b.step();
  EXPECT_TRUE(hasNote(b.last, "localiser uncertain again: replanning"));
  EXPECT_TRUE(b.last.new_plan);
  EXPECT_EQ(b.plans_asked, 2);
  EXPECT_FALSE(b.runner->holding());
  EXPECT_EQ(b.runner->counts().relocalisation_waits, 1);
  // At the goal, an uncertain pose is not judged: the robot waits there for a certain one.
  ASSERT_TRUE(b.runToArrival(30.0));
  EXPECT_FALSE(b.runUntil([&] { return b.finished(); }, 3.0));
  EXPECT_TRUE(b.runner->holding());
  b.runner->setLocalizerStatus(tn::LocalizerState::kLocalized, b.now_s);
  ASSERT_TRUE(b.runUntil([&] { return b.finished(); }, 1.0));
  EXPECT_EQ(b.last.state, GoalState::kSucceeded);
  EXPECT_TRUE(hasNote(b.last, "localiser localized again at the goal"));
  EXPECT_EQ(b.runner->counts().relocalisation_waits, 2);
}

// Lost for longer than localization_lost_wait: the goal is given up with the gate's reason, the robot still.
TEST(GoalRunner, ALocaliserLostTooLongAbortsTheGoal) {
  Bench b([](tn::GoalRunnerParams& p) { p.gate.lost_wait_s = 2.0; });
  b.runner->accept({4.0, 0.0, 0.0}, b.now_s);
  ASSERT_TRUE(b.runUntil([&] { return b.pose.x > 1.0; }, 30.0));
  b.runner->setLocalizerStatus(tn::LocalizerState::kLost, b.now_s);
  const Pose2D held = b.pose;
  const double lost_s = b.now_s;
  ASSERT_TRUE(b.runUntil([&] { return b.finished(); }, 5.0));
  EXPECT_EQ(b.last.state, GoalState::kAborted);
  EXPECT_EQ(b.last.command, DriveCommand::kStop);
  EXPECT_NE(b.last.reason.find("localiser lost for"), std::string::npos) << b.last.reason;
  EXPECT_GT(b.now_s - kDt - lost_s, 2.0);
  EXPECT_EQ(distance(b.pose, held), 0.0);
}

// Each goal has its own goal_corrections: the second goal corrects again after the first used them up.
TEST(GoalRunner, EachGoalGetsItsOwnCorrections) {
  Bench b([](tn::GoalRunnerParams& p) { p.goal_corrections = 1; });
  for (const Pose2D& goal : {Pose2D{2.0, 0.0, 0.0}, Pose2D{3.5, 0.5, 0.3}}) {
    b.runner->accept(goal, b.now_s);
    ASSERT_TRUE(b.runToArrival(30.0));
    b.pose.x += 0.05;  // slides once after stopping
    ASSERT_TRUE(b.runUntil([&] { return b.finished(); }, 60.0));
    EXPECT_EQ(b.last.state, GoalState::kSucceeded) << b.last.reason;
    EXPECT_TRUE(hasNote(b.last, "1 corrections"));
  }
  EXPECT_EQ(b.approaches_asked, 2);
}

// The node's planners on a costmap: a differential robot's plan ends with the final approach, a lidar point on the
// path is an obstacle ahead, and a renewed approach backs off to the final approach's start.
TEST(GoalRunner, CostmapPlannersPlanOnTheCostmapAndSeeObstaclesAhead) {
  thorvald_map::OccupancyGrid map(160, 100, 0.05, 0.0, 0.0, thorvald_map::kFree);
  for (int x = 0; x < map.width; ++x) map.at(x, 0) = map.at(x, map.height - 1) = thorvald_map::kOccupied;
  for (int y = 0; y < map.height; ++y) map.at(0, y) = map.at(map.width - 1, y) = thorvald_map::kOccupied;
  tn::Costmap cm(map, thorvald_map::OccupancyGrid{}, tn::CostmapParams{});
  const tn::GoalPlanners p =
      tn::costmapPlanners([&]() -> const tn::Costmap& { return cm; }, tn::rectangleFootprint(-0.3, 0.3, -0.25, 0.25),
                          tn::PlannerParams{}, 0.3, 1.5, false);
  const Pose2D start{1.0, 2.5, 0.0}, goal{6.0, 2.5, 0.0};
  const tn::GoalPlan r = p.plan(start, goal);
  ASSERT_TRUE(r.ok) << r.error;
  ASSERT_GE(r.path.size(), 2u);
  EXPECT_LT((r.path.back() - Eigen::Vector2d(6.0, 2.5)).norm(), 1e-9);
  EXPECT_LT((r.path.end()[-2] - Eigen::Vector2d(5.7, 2.5)).norm(), 1e-6);
  EXPECT_FALSE(p.obstacle_ahead(start, r.path, 1, goal.yaw, false));
  cm.setObstacles({{2.0, 2.5}});
  EXPECT_TRUE(p.obstacle_ahead(start, r.path, 1, goal.yaw, false));
  const tn::Approach a = p.approach_again({5.95, 2.55, 0.0}, goal);
  EXPECT_TRUE(a.reverse);
  EXPECT_TRUE(a.then_to_goal);
  EXPECT_NEAR(a.first_target.x, 5.7, 1e-6);
  EXPECT_NEAR(a.first_target.y, 2.5, 1e-6);
}

}  // namespace
