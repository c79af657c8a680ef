#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>

#include "test_robots.h"
#include "thorvald_base/angles.h"
#include "thorvald_base/standard_calculator.h"

using namespace thorvald_base;

namespace {

std::unique_ptr<BaseCalculator> makeCalculator(const test::TestRobot& robot, const std::string& estimator) {
  std::unique_ptr<BaseCalculator> c;
  if (robot.calculator == "diff") c = std::make_unique<DiffDriveCalculator>();
  if (robot.calculator == "one_wheel") c = std::make_unique<OneWheelCalculator>();
  if (robot.calculator == "standard") c = std::make_unique<StandardCalculator>();
  CalculatorOptions options;
  options.estimator = estimator;
  c->configure(robot.config.drives, robot.config.passive_wheels, options);
  return c;
}

/// Joint states of wheels that have reached their commands.
std::vector<DriveFeedback> reached(const std::vector<DriveCommand>& cmds) {
  std::vector<DriveFeedback> fb(cmds.size());
  for (size_t i = 0; i < cmds.size(); ++i) {
    fb[i].steering_rad = cmds[i].steering_rad;
    fb[i].wheel_speed_radps = cmds[i].wheel_speed_radps;
    fb[i].valid = true;
  }
  return fb;
}

class PaperRobots : public testing::TestWithParam<std::string> {};

}  // namespace

TEST_P(PaperRobots, RandomTwistsRoundTripWithinLimits) {
  for (const auto& robot : test::paperRobots()) {
    SCOPED_TRACE(robot.name);
    if (robot.calculator == "diff" && GetParam() != "least_squares") continue;  // refused: see below
    auto calc = makeCalculator(robot, GetParam());
    std::mt19937 rng(42);
    std::uniform_real_distribution<double> v(-1.5, 1.5), w(-1.0, 1.0);
    std::vector<DriveCommand> previous(robot.config.drives.size());
    std::vector<DriveFeedback> current = reached(previous);
    int flips = 0;
    for (int k = 0; k < 300; ++k) {
      const Twist2D cmd{v(rng), v(rng), w(rng)};
      // Iterate until the steering has reached its target (the model scales propulsion down until then).
      std::vector<DriveCommand> out;
      for (int pass = 0; pass < 2; ++pass) {
        out = calc->computeCommands(cmd, current, previous);
        current = reached(out);
      }
      for (size_t i = 0; i < out.size(); ++i) {
        const auto& d = robot.config.drives[i];
        ASSERT_TRUE(std::isfinite(out[i].wheel_speed_radps));
        if (d.steered()) {
          ASSERT_LE(std::fabs(out[i].steering_rad), d.str_lim + 1e-12);
          const double wanted = std::atan2(cmd.vy + cmd.wz * d.x, cmd.vx - cmd.wz * d.y);
          if (std::fabs(angleDiff(wanted, out[i].steering_rad)) > kPi / 2) ++flips;
        } else {
          ASSERT_EQ(out[i].steering_rad, 0.0);
        }
      }
      const Twist2D want = calc->achievable(cmd);
      const VelocityEstimate est = calc->estimateTwist(current);
      ASSERT_TRUE(est.valid);
      // Independent check: each wheel's commanded ground velocity equals the rigid-body field of `want`.
      for (size_t i = 0; i < out.size(); ++i) {
        const auto& d = robot.config.drives[i];
        const double s = out[i].wheel_speed_radps * d.r_wheel;
        EXPECT_NEAR(s * std::cos(out[i].steering_rad), want.vx - want.wz * d.y, 1e-9);
        EXPECT_NEAR(s * std::sin(out[i].steering_rad), want.vy + want.wz * d.x, 1e-9);
      }
      // The paper's estimator takes nearly parallel wheel normals (|wz| tiny) for straight driving.
      const bool near_straight = std::fabs(want.wz) < 0.01;
      const double tol = GetParam() == "random_pairs" ? (near_straight ? 0.03 : 1e-6) : 1e-9;
      EXPECT_NEAR(est.twist.vx, want.vx, tol);
      EXPECT_NEAR(est.twist.vy, want.vy, tol);
      EXPECT_NEAR(est.twist.wz, want.wz, tol);
      previous = out;
    }
    if (robot.calculator == "standard" && robot.name.find("2ws") == std::string::npos) {
      EXPECT_GT(flips, 0);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Estimators, PaperRobots, testing::Values("least_squares", "random_pairs"));

TEST(Kinematics, FixedWheelsDropLateralSpeed) {
  for (const auto& robot : test::paperRobots()) {
    if (robot.calculator == "standard" && robot.name.find("2ws") == std::string::npos) continue;
    SCOPED_TRACE(robot.name);
    auto calc = makeCalculator(robot, "least_squares");
    // Pure lateral command: nothing of it is achievable, and no wheel fights the others.
    const Twist2D lateral{0.0, 0.5, 0.0};
    const Twist2D a = calc->achievable(lateral);
    EXPECT_NEAR(a.vx, 0.0, 1e-12);
    EXPECT_NEAR(a.vy, 0.0, 1e-12);
    std::vector<DriveCommand> prev(robot.config.drives.size());
    for (const auto& c : calc->computeCommands(lateral, reached(prev), prev))
      EXPECT_NEAR(c.wheel_speed_radps, 0, 1e-12);
  }
}

TEST(Kinematics, ZeroCommandKeepsSteering) {
  auto robot = test::paperRobots()[0];
  auto calc = makeCalculator(robot, "least_squares");
  std::vector<DriveCommand> prev(4);
  for (auto& p : prev) p.steering_rad = 0.7;
  const auto out = calc->computeCommands({}, reached(prev), prev);
  for (const auto& c : out) {
    EXPECT_DOUBLE_EQ(c.steering_rad, 0.7);
    EXPECT_DOUBLE_EQ(c.wheel_speed_radps, 0.0);
  }
}

TEST(Kinematics, PureTranslationSteersAllWheelsAlike) {
  auto robot = test::paperRobots()[7];  // 9WD9WS
  auto calc = makeCalculator(robot, "least_squares");
  std::vector<DriveCommand> prev(9);
  std::vector<DriveFeedback> fb = reached(prev);
  std::vector<DriveCommand> out;
  for (int pass = 0; pass < 2; ++pass) fb = reached(out = calc->computeCommands({0.3, 0.3, 0.0}, fb, prev));
  for (const auto& c : out) {
    EXPECT_NEAR(c.steering_rad, kPi / 4, 1e-12);
    EXPECT_NEAR(c.wheel_speed_radps, std::hypot(0.3, 0.3) / 0.2, 1e-12);
  }
}

TEST(Kinematics, PropulsionWaitsForSteering) {
  auto robot = test::paperRobots()[0];
  auto calc = makeCalculator(robot, "least_squares");
  std::vector<DriveCommand> prev(4);
  // Wheels straight, command a crab move: wheels must turn 90 deg first, so no propulsion yet.
  const Twist2D crab{0.0, 0.3, 0.0};
  auto out = calc->computeCommands(crab, reached(prev), prev);
  for (const auto& c : out) EXPECT_DOUBLE_EQ(c.wheel_speed_radps, 0.0);
  // Halfway there: some propulsion, the same scale on every wheel.
  std::vector<DriveFeedback> half = reached(out);
  for (auto& h : half) h.steering_rad *= 0.9;
  const auto full = calc->computeCommands(crab, reached(out), out);
  const auto part = calc->computeCommands(crab, half, out);
  const double scale = part[0].wheel_speed_radps / full[0].wheel_speed_radps;
  EXPECT_GT(scale, 0.0);
  EXPECT_LT(scale, 1.0);
  for (size_t i = 0; i < 4; ++i) EXPECT_NEAR(part[i].wheel_speed_radps, scale * full[i].wheel_speed_radps, 1e-12);
}

TEST(Kinematics, ModelsRejectRobotsTheyCannotDrive) {
  const auto robots = test::paperRobots();
  DiffDriveCalculator diff;
  EXPECT_THROW(diff.configure(robots[0].config.drives, {}, {}), ConfigError);
  OneWheelCalculator one;
  EXPECT_THROW(one.configure(robots[0].config.drives, {}, {}), ConfigError);
  EXPECT_THROW(one.configure(robots[3].config.drives, {}, {}), ConfigError);  // no passive wheels
  StandardCalculator standard;
  CalculatorOptions bad;
  bad.estimator = "magic";
  EXPECT_THROW(standard.configure(robots[0].config.drives, {}, bad), ConfigError);
  EXPECT_THROW(standard.configure({}, {}, {}), ConfigError);
}

TEST(Kinematics, EveryModelValidatesTheOdometryEstimator) {
  const auto robots = test::paperRobots();
  CalculatorOptions magic, pairs;
  magic.estimator = "magic";
  pairs.estimator = "random_pairs";
  for (const auto& robot : robots) {
    SCOPED_TRACE(robot.name);
    auto calc = makeCalculator(robot, "least_squares");
    EXPECT_THROW(calc->configure(robot.config.drives, robot.config.passive_wheels, magic), ConfigError);
  }
  // Two parallel fixed wheels: random pairs never intersect, so every model with only fixed wheels refuses it.
  DiffDriveCalculator diff;
  EXPECT_THROW(diff.configure(robots[4].config.drives, {}, pairs), ConfigError);
  StandardCalculator skid;
  try {
    skid.configure(robots[4].config.drives, {}, pairs);
    ADD_FAILURE() << "random_pairs accepted on fixed wheels only";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("least_squares"), std::string::npos) << e.what();
  }
}

TEST(Kinematics, ModelsRefuseDegenerateGeometry) {
  std::vector<DriveConfig> same_place = {test::drive(0, 0.5, 0.5), test::drive(1, 0.5, 0.5), test::drive(2, 0.5, 0.5)};
  StandardCalculator standard;
  EXPECT_THROW(standard.configure(same_place, {}, {}), ConfigError);
  // One steered drive alone leaves rotation and translation mixed up.
  EXPECT_THROW(standard.configure({test::drive(0, 0.6, 0.0)}, {}, {}), ConfigError);
  // A passive wheel on the drive's own axle line (same x) does not help; one off it does.
  EXPECT_THROW(standard.configure({test::drive(0, 0.6, 0.0)}, {test::passive(0.6, 0.4)}, {}), ConfigError);
  EXPECT_NO_THROW(standard.configure({test::drive(0, 0.6, 0.0)}, {test::passive(-0.4, 0.4)}, {}));
}
