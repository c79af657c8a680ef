// Unit tests of the ROS-free parts of the UV mission: surface classification, the alignment manoeuvre, the rail
// search, motions on odometry and the rail run's speed profile.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numeric>
#include <random>

#include "greenhouse_rail_nav/odometry_motion.h"
#include "greenhouse_rail_nav/rail_alignment.h"
#include "greenhouse_rail_nav/rail_run.h"
#include "greenhouse_rail_nav/surface_classifier.h"

namespace grn = greenhouse_rail_nav;

TEST(SurfaceClassifier, ClassifiesFloorRailEdgeAndUnknown) {
  grn::SurfaceClassifierParams p;  // floor 0.35, rail top 0.055 above it
  ASSERT_EQ(p.validate(), "");
  EXPECT_EQ(grn::classifyRange(0.351, p), grn::Surface::kFloor);
  EXPECT_EQ(grn::classifyRange(0.296, p), grn::Surface::kRail);
  EXPECT_EQ(grn::classifyRange(0.50, p), grn::Surface::kEdge);  // the rows' ground, 0.15 m lower
  EXPECT_EQ(grn::classifyRange(std::numeric_limits<double>::infinity(), p), grn::Surface::kEdge);
  EXPECT_EQ(grn::classifyRange(std::numeric_limits<double>::quiet_NaN(), p), grn::Surface::kUnknown);
  EXPECT_EQ(grn::classifyRange(0.323, p), grn::Surface::kUnknown);  // between floor and rail: not decided
  EXPECT_EQ(grn::classifyRange(0.10, p), grn::Surface::kUnknown);   // something close under the sensor
}

TEST(SurfaceClassifier, RejectsParametersThatCannotTellFloorFromRail) {
  grn::SurfaceClassifierParams p;
  p.tolerance_m = 0.03;  // 2 x 0.03 > 0.055
  EXPECT_NE(p.validate().find("cannot be told apart"), std::string::npos);
  p = grn::SurfaceClassifierParams();
  p.confirm_readings = 0;
  EXPECT_NE(p.validate().find("confirm_readings"), std::string::npos);
}

TEST(SurfaceTracker, DebouncesChangesButReportsAnEdgeAtOnce) {
  grn::SurfaceClassifierParams p;
  p.confirm_readings = 3;
  grn::SurfaceTracker t(p, 2);
  for (int i = 0; i < 3; ++i) t.update(0, 0.35);
  EXPECT_EQ(t.surface(0), grn::Surface::kFloor);
  t.update(0, 0.295);
  t.update(0, 0.295);
  EXPECT_EQ(t.surface(0), grn::Surface::kFloor) << "two rail readings must not switch yet";
  t.update(0, 0.295);
  EXPECT_EQ(t.surface(0), grn::Surface::kRail);
  EXPECT_EQ(t.update(0, 0.6), grn::Surface::kEdge) << "an edge must be reported on the first reading";
  for (int i = 0; i < 3; ++i) t.update(1, 0.295);
  EXPECT_EQ(t.common({0, 1}), grn::Surface::kEdge);
  for (int i = 0; i < 3; ++i) t.update(0, 0.295);
  EXPECT_EQ(t.common({0, 1}), grn::Surface::kRail);
  for (int i = 0; i < 3; ++i) t.update(0, 0.35);
  EXPECT_EQ(t.common({0, 1}), grn::Surface::kUnknown) << "floor under one, rail under the other";
  EXPECT_EQ(t.common({}), grn::Surface::kUnknown);
}

TEST(RailAlignment, EveryPlanEndsOnTheApproachPoseWithinTheTurnLimit) {
  grn::AlignmentParams p;
  ASSERT_EQ(p.validate(), "");
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(-2.5, -0.2), uy(-0.6, 0.6), uyaw(-0.8, 0.8);
  for (int i = 0; i < 2000; ++i) {
    const thorvald_base::Pose2D start(ux(rng), uy(rng), uyaw(rng));
    const auto plan = grn::planAlignment(start, p);
    const thorvald_base::Pose2D end = grn::applyPlan(start, plan);
    EXPECT_NEAR(end.x, p.approach_x_m, p.min_step_m + 1e-9) << "start " << start.x << " " << start.y;
    EXPECT_NEAR(end.y, 0.0, p.min_step_m + 1e-9);
    EXPECT_NEAR(end.yaw, 0.0, p.min_rotation_rad + 1e-9);
    EXPECT_LE(plan.size(), 5u);
    // The diagonal leg never points more than max_turn away from the rails' direction.
    thorvald_base::Pose2D pose = start;
    for (const auto& s : plan) {
      if (s.kind == grn::MotionStep::Kind::kTranslate) {
        // A residual yaw below min_rotation is not turned away first.
        EXPECT_LE(std::fabs(pose.yaw), p.max_turn_rad + p.min_rotation_rad + 1e-9) << s.label;
      }
      pose = grn::applyPlan(pose, {s});
    }
  }
}

TEST(RailAlignment, SmallOffsetsNeedFewSteps) {
  grn::AlignmentParams p;
  EXPECT_TRUE(grn::planAlignment({p.approach_x_m, 0.0, 0.0}, p).empty());
  const auto only_rotate = grn::planAlignment({p.approach_x_m, 0.0, 0.1}, p);
  ASSERT_EQ(only_rotate.size(), 1u);
  EXPECT_NEAR(only_rotate[0].amount, -0.1, 1e-12);
  // Too close to the rails with a lateral offset: the robot must reverse first.
  const auto plan = grn::planAlignment({-0.7, 0.15, 0.0}, p);
  ASSERT_GE(plan.size(), 2u);
  EXPECT_EQ(plan[0].kind, grn::MotionStep::Kind::kTranslate);
  EXPECT_LT(plan[0].amount, 0.0);
  EXPECT_TRUE(grn::planAlignment({std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0}, p).empty());
}

// A few centimetres off the centre line, the turn towards it is small (atan(|y| / run_up)): the frame's corners
// (1.1 m x 1.02 m about base_link) swing out little, where a turn of max_turn swept them 0.2 m out, into the side wall
// beside an outer rail set.
TEST(RailAlignment, SmallSidewaysOffsetsTurnLittle) {
  grn::AlignmentParams p;
  for (const double y : {0.025, 0.04, -0.06, 0.1}) {
    const auto plan = grn::planAlignment({p.approach_x_m - 0.02, y, 0.0}, p);
    double largest_turn = 0.0;
    for (const auto& s : plan)
      if (s.kind == grn::MotionStep::Kind::kRotate) largest_turn = std::max(largest_turn, std::fabs(s.amount));
    EXPECT_NEAR(largest_turn, std::atan2(std::fabs(y), p.run_up_m), 0.02) << "y " << y;
    // How far the frame's corners swing out sideways in that turn.
    const double half_length = 0.55, half_width = 0.51;
    const double swing = half_width * std::cos(largest_turn) + half_length * std::sin(largest_turn) - half_width;
    EXPECT_LT(swing, 0.2) << "y " << y;
    const thorvald_base::Pose2D end = grn::applyPlan({p.approach_x_m - 0.02, y, 0.0}, plan);
    EXPECT_NEAR(end.y, 0.0, p.min_step_m + 1e-9);
  }
}

TEST(RailAlignment, EntryLimits) {
  grn::AlignmentParams p;
  EXPECT_TRUE(grn::withinEntryLimits({p.approach_x_m, 0.01, 0.01}, true, p));
  EXPECT_FALSE(grn::withinEntryLimits({p.approach_x_m, 0.03, 0.0}, true, p));
  EXPECT_FALSE(grn::withinEntryLimits({p.approach_x_m, 0.0, 0.03}, true, p));
  EXPECT_FALSE(grn::withinEntryLimits({p.approach_x_m - 1.0, 0.0, 0.0}, true, p));
  EXPECT_TRUE(grn::withinEntryLimits({p.approach_x_m - 1.0, 0.0, 0.0}, false, p)) << "x unobserved is not used";
  EXPECT_FALSE(grn::withinEntryLimits({std::numeric_limits<double>::quiet_NaN(), 0.0, 0.0}, false, p));
}

TEST(RailSearch, AlternatesThroughGrowingAnglesAndReturns) {
  const auto r = grn::railSearchRotations(0.2, 0.6);
  std::vector<double> heading;
  double h = 0.0;
  for (double d : r) heading.push_back(h += d);
  const std::vector<double> expected = {0.2, -0.2, 0.4, -0.4, 0.6, -0.6, 0.0};
  ASSERT_EQ(heading.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_NEAR(heading[i], expected[i], 1e-12) << i;
  EXPECT_TRUE(grn::railSearchRotations(0.0, 1.0).empty());
  EXPECT_TRUE(grn::railSearchRotations(0.5, 0.1).empty());
}

namespace {
// A differential robot whose speeds follow the command with a first-order lag, with a small yaw drift while
// driving (a slightly larger wheel on one side).
struct LaggedRobot {
  thorvald_base::Pose2D pose;
  double v = 0.0, w = 0.0;
  double lag_s = 0.15;
  void step(double v_cmd, double w_cmd, double dt) {
    const double a = dt / lag_s;
    v += a * (v_cmd - v);
    w += a * (w_cmd - w);
    pose.yaw = thorvald_base::normalizeAngle(pose.yaw + (w + 0.02 * v) * dt);
    pose.x += v * std::cos(pose.yaw) * dt;
    pose.y += v * std::sin(pose.yaw) * dt;
  }
};
}  // namespace

TEST(OdometryMotion, ExecutesAnAlignmentPlanOnALaggedRobot) {
  grn::MotionLimits limits;
  ASSERT_EQ(limits.validate(), "");
  grn::AlignmentParams p;
  for (const thorvald_base::Pose2D start :
       {thorvald_base::Pose2D(-1.2, 0.25, 0.3), thorvald_base::Pose2D(-0.6, -0.3, -0.2),
        thorvald_base::Pose2D(-2.0, 0.05, 0.05), thorvald_base::Pose2D(-0.9, 0.0, 3.0)}) {
    LaggedRobot robot;
    robot.pose = start;
    grn::OdometryMotion motion(limits);
    double t = 0.0;
    const double dt = 0.02;
    for (const auto& s : grn::planAlignment(start, p)) {
      motion.start(s, robot.pose, t);
      grn::OdometryMotion::Command c;
      for (int i = 0; i < 3000 && !c.done; ++i) {
        c = motion.update(robot.pose, t);
        ASSERT_FALSE(c.failed) << c.reason;
        robot.step(c.linear_mps, c.angular_rps, dt);
        t += dt;
      }
      ASSERT_TRUE(c.done) << s.label;
      for (int i = 0; i < 50; ++i, t += dt) robot.step(0.0, 0.0, dt);  // let the lag settle between steps
    }
    // Lag and drift leave a residual; it must be inside the entry limits so that one retry is rarely needed.
    EXPECT_NEAR(robot.pose.x, p.approach_x_m, 0.02);
    EXPECT_NEAR(robot.pose.y, 0.0, p.y_limit_m);
    EXPECT_NEAR(robot.pose.yaw, 0.0, p.yaw_limit_rad);
  }
}

// Short rotations and the steps after them, back to back as the mission runs them, on a base whose lag (0.12 s) is
// not the one the motion assumes (0.15 s): each rotation must turn its angle. Before, a step ended while the base
// was still turning and the next one's heading hold cut the rest off, and the lag was counted from the commanded
// rate the base had not reached yet: a 0.037 rad rotation turned 0.019 rad, and the mission gave up on a rail set
// "still outside the limits" after its alignments.
TEST(OdometryMotion, ShortRotationsTurnTheirAngleWithTheNextStepRightAfter) {
  grn::MotionLimits limits;
  for (const double angle : {0.01, 0.03, 0.05, 0.1, -0.04, 0.6}) {
    LaggedRobot robot;
    robot.lag_s = 0.12;
    grn::OdometryMotion motion(limits);
    double t = 0.0;
    for (const grn::MotionStep& s : {grn::MotionStep{grn::MotionStep::Kind::kRotate, angle, "rotate"},
                                     grn::MotionStep{grn::MotionStep::Kind::kTranslate, 0.3, "drive"}}) {
      motion.start(s, robot.pose, t);
      grn::OdometryMotion::Command c;
      for (int i = 0; i < 3000 && !c.done; ++i, t += 0.02) {
        c = motion.update(robot.pose, t);
        ASSERT_FALSE(c.failed) << c.reason;
        robot.step(c.linear_mps, c.angular_rps, 0.02);
      }
      ASSERT_TRUE(c.done) << s.label;
    }
    // The drive's own yaw drift (0.02 rad per metre) is held by its heading hold.
    EXPECT_NEAR(robot.pose.yaw, angle, 0.008) << "rotation of " << angle << " rad";
  }
}

TEST(OdometryMotion, RotationsBeyondPiAndStalls) {
  grn::MotionLimits limits;
  grn::OdometryMotion motion(limits);
  LaggedRobot robot;
  double t = 0.0;
  motion.start({grn::MotionStep::Kind::kRotate, 4.0, "spin"}, robot.pose, t);
  grn::OdometryMotion::Command c;
  double turned = 0.0;
  for (int i = 0; i < 5000 && !c.done; ++i, t += 0.02) {
    c = motion.update(robot.pose, t);
    const double before = robot.pose.yaw;
    robot.step(c.linear_mps, c.angular_rps, 0.02);
    turned += thorvald_base::normalizeAngle(robot.pose.yaw - before);
  }
  ASSERT_TRUE(c.done);
  EXPECT_NEAR(turned, 4.0, 0.02);

  // A robot that does not move: the motion fails after the stall timeout and commands zero.
  motion.start({grn::MotionStep::Kind::kTranslate, 1.0, "blocked"}, thorvald_base::Pose2D(), 100.0);
  c = motion.update(thorvald_base::Pose2D(), 100.0 + limits.stall_timeout_s - 0.5);
  EXPECT_FALSE(c.failed);
  c = motion.update(thorvald_base::Pose2D(), 100.0 + limits.stall_timeout_s + 0.5);
  EXPECT_TRUE(c.failed);
  EXPECT_EQ(c.linear_mps, 0.0);
  EXPECT_NE(c.reason.find("no progress"), std::string::npos);
  motion.start({grn::MotionStep::Kind::kTranslate, 1.0, "nan"}, thorvald_base::Pose2D(), 0.0);
  c = motion.update(thorvald_base::Pose2D(std::numeric_limits<double>::quiet_NaN(), 0, 0), 0.1);
  EXPECT_TRUE(c.failed);
}

TEST(RailRun, ForwardRangeIsTheMedianAhead) {
  std::vector<float> ranges(181, 10.0f);  // -90..90 deg, 1 deg apart
  const double inc = M_PI / 180.0;
  ranges[90] = 0.5f;  // one outlier straight ahead (a leaf)
  ranges[89] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NEAR(grn::forwardRange(ranges, -M_PI / 2, inc, 0.05, 0.1, 30.0), 10.0, 1e-6);
  EXPECT_TRUE(std::isnan(grn::forwardRange({}, -1.0, 0.01, 0.05, 0.1, 30.0)));
  EXPECT_TRUE(std::isnan(grn::forwardRange(ranges, -M_PI / 2, 0.0, 0.05, 0.1, 30.0)));
  std::vector<float> none(181, std::numeric_limits<float>::infinity());
  EXPECT_TRUE(std::isnan(grn::forwardRange(none, -M_PI / 2, inc, 0.05, 0.1, 30.0)));
}

TEST(RailRun, DrivesAtTreatmentSpeedAndStopsBeforeTheWall) {
  grn::RailRunParams p;
  ASSERT_EQ(p.validate(), "");
  double wall = 21.0, v = 0.0, t = 0.0, cruise_time = 0.0;
  const double dt = 0.02;
  for (int i = 0; i < 10000; ++i, t += dt) {
    v = grn::inboundSpeed(p, v, wall, dt);
    if (v == 0.0 && t > 1.0) break;
    if (std::fabs(v - p.treat_speed_mps) < 1e-9) cruise_time += dt;
    wall -= v * dt;
  }
  EXPECT_EQ(v, 0.0);
  EXPECT_NEAR(wall, p.end_wall_range_m, 0.02);
  EXPECT_GT(cruise_time, 35.0) << "most of the 19.7 m must be driven at 0.5 m/s";
  // No wall in sight: full treatment speed after the ramp.
  v = 0.0;
  for (int i = 0; i < 100; ++i) v = grn::inboundSpeed(p, v, std::numeric_limits<double>::quiet_NaN(), dt);
  EXPECT_DOUBLE_EQ(v, p.treat_speed_mps);
  EXPECT_DOUBLE_EQ(grn::returnSpeed(p, p.slow_speed_mps, 18.5, 20.0, dt), p.slow_speed_mps);
  EXPECT_DOUBLE_EQ(grn::returnSpeed(p, p.return_speed_mps, 5.0, 20.0, dt), p.return_speed_mps);
}
