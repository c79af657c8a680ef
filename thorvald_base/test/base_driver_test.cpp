#include <gmock/gmock.h>

#include <cmath>

#include "test_robots.h"
#include "thorvald_base/base_driver.h"
#include "thorvald_base/testing/ideal_base.h"
#include "thorvald_base/standard_calculator.h"

using namespace thorvald_base;
using testing::_;
using testing::AllOf;
using testing::Field;
using testing::HasSubstr;
using testing::NiceMock;
using testing::Return;

namespace {

class MockDrive : public MotorDrive {
 public:
  MOCK_METHOD(void, setCommand, (const DriveCommand&), (override));
  MOCK_METHOD(void, update, (double), (override));
  MOCK_METHOD(DriveFeedback, feedback, (), (const, override));
  MOCK_METHOD(DriveStatus, status, (), (const, override));
  MOCK_METHOD(void, reconfigure, (const DriveConfig&), (override));
  MOCK_METHOD(bool, startHoming, (), (override));
  MOCK_METHOD(void, clearFault, (), (override));
};

class MockBattery : public Battery {
 public:
  MOCK_METHOD(const std::string&, name, (), (const, override));
  MOCK_METHOD(void, update, (double), (override));
  MOCK_METHOD(BatteryReading, reading, (), (const, override));
};

DriveFeedback straight() {
  DriveFeedback f;
  f.valid = true;
  return f;
}

/// A 4WD4WS robot on mock drives whose wheels stand straight.
struct Rig {
  std::vector<MockDrive*> drives;
  std::unique_ptr<BaseDriver> driver;
  DriveStatus ok;

  Rig() {
    RobotConfig config = test::paperRobots()[0].config;
    std::vector<std::unique_ptr<MotorDrive>> owned;
    for (int i = 0; i < 4; ++i) {
      auto d = std::make_unique<NiceMock<MockDrive>>();
      ON_CALL(*d, feedback()).WillByDefault(Return(straight()));
      ON_CALL(*d, status()).WillByDefault(Return(ok));
      drives.push_back(d.get());
      owned.push_back(std::move(d));
    }
    driver = std::make_unique<BaseDriver>(config, std::make_unique<StandardCalculator>(), std::move(owned),
                                          std::vector<std::unique_ptr<Battery>>{}, BaseDriverOptions{});
  }
};

auto speed(double radps) { return Field(&DriveCommand::wheel_speed_radps, testing::DoubleNear(radps, 1e-9)); }
auto steering(double rad) { return Field(&DriveCommand::steering_rad, testing::DoubleNear(rad, 1e-9)); }

}  // namespace

TEST(BaseDriver, CommandsEveryDriveForForwardMotion) {
  Rig rig;
  for (auto* d : rig.drives) {
    EXPECT_CALL(*d, setCommand(AllOf(speed(0.5 / 0.2), steering(0.0))));
    EXPECT_CALL(*d, update(1.0));
  }
  ASSERT_TRUE(rig.driver->setCommand({0.5, 0.0, 0.0}, 1.0));
  rig.driver->update(1.0);
  EXPECT_EQ(rig.driver->stopReason(), StopReason::kNone);
}

TEST(BaseDriver, FaultedDriveStopsAllPropulsionAtOnceAndLatches) {
  Rig rig;
  DriveStatus fault;
  fault.fault = true;
  fault.text = "stall";
  EXPECT_CALL(*rig.drives[2], status()).WillRepeatedly(Return(fault));
  for (auto* d : rig.drives) EXPECT_CALL(*d, setCommand(speed(0.0))).Times(testing::AtLeast(1));
  rig.driver->setCommand({0.5, 0.0, 0.0}, 1.0);
  rig.driver->update(1.0);
  EXPECT_TRUE(rig.driver->driveStop());
  EXPECT_THAT(rig.driver->driveStopText(), testing::HasSubstr("drive2: stall"));
  EXPECT_CALL(*rig.drives[2], clearFault());
  std::string why;
  EXPECT_FALSE(rig.driver->clearDriveStop(&why));
  EXPECT_THAT(why, testing::HasSubstr("drive2"));

  // The fault goes away after the clear request: the stop is released in that cycle, no second call needed.
  for (auto* d : rig.drives) testing::Mock::VerifyAndClearExpectations(d);
  ON_CALL(*rig.drives[2], status()).WillByDefault(Return(rig.ok));
  for (auto* d : rig.drives) EXPECT_CALL(*d, setCommand(speed(2.5)));
  rig.driver->setCommand({0.5, 0.0, 0.0}, 1.02);
  rig.driver->update(1.02);
  EXPECT_EQ(rig.driver->stopReason(), StopReason::kNone);
  EXPECT_FALSE(rig.driver->driveStop());
}

TEST(BaseDriver, AFaultThatGoesAwayWithoutAClearRequestStaysLatched) {
  Rig rig;
  DriveStatus fault;
  fault.fault = true;
  fault.text = "stall";
  EXPECT_CALL(*rig.drives[1], status()).WillRepeatedly(Return(fault));
  rig.driver->setCommand({0.5, 0.0, 0.0}, 1.0);
  rig.driver->update(1.0);
  testing::Mock::VerifyAndClearExpectations(rig.drives[1]);
  ON_CALL(*rig.drives[1], status()).WillByDefault(Return(rig.ok));
  rig.driver->setCommand({0.5, 0.0, 0.0}, 1.02);
  rig.driver->update(1.02);
  EXPECT_EQ(rig.driver->stopReason(), StopReason::kDriveStop);
  std::string why;
  EXPECT_TRUE(rig.driver->clearDriveStop(&why));
  for (auto* d : rig.drives) EXPECT_CALL(*d, setCommand(speed(2.5)));
  rig.driver->update(1.04);
}

TEST(BaseDriver, OneClearRequestClearsEveryFaultedDrive) {
  Rig rig;
  DriveStatus fault, lost;
  fault.fault = true;
  fault.text = "over current";
  lost.online = false;
  ON_CALL(*rig.drives[0], status()).WillByDefault(Return(fault));
  ON_CALL(*rig.drives[3], status()).WillByDefault(Return(lost));
  rig.driver->setCommand({0.5, 0.0, 0.0}, 1.0);
  rig.driver->update(1.0);
  ASSERT_TRUE(rig.driver->driveStop());
  EXPECT_CALL(*rig.drives[0], clearFault());
  EXPECT_CALL(*rig.drives[3], clearFault());
  EXPECT_CALL(*rig.drives[1], clearFault()).Times(0);
  std::string why;
  EXPECT_FALSE(rig.driver->clearDriveStop(&why));
  EXPECT_THAT(why, testing::HasSubstr("drive0 still over current"));
  EXPECT_THAT(why, testing::HasSubstr("drive3 still lost"));
  // Both recover; one cycle later the base drives again.
  ON_CALL(*rig.drives[0], status()).WillByDefault(Return(rig.ok));
  ON_CALL(*rig.drives[3], status()).WillByDefault(Return(rig.ok));
  rig.driver->setCommand({0.5, 0.0, 0.0}, 1.02);
  rig.driver->update(1.02);
  EXPECT_FALSE(rig.driver->driveStop());
  EXPECT_EQ(rig.driver->stopReason(), StopReason::kNone);
}

TEST(BaseDriver, AClearRequestExpires) {
  Rig rig;
  DriveStatus fault;
  fault.fault = true;
  ON_CALL(*rig.drives[2], status()).WillByDefault(Return(fault));
  rig.driver->update(1.0);
  std::string why;
  EXPECT_FALSE(rig.driver->clearDriveStop(&why));
  rig.driver->update(1.02);
  rig.driver->update(3.5);  // past the 2 s window, still faulted
  ON_CALL(*rig.drives[2], status()).WillByDefault(Return(rig.ok));
  rig.driver->update(3.52);
  EXPECT_TRUE(rig.driver->driveStop());
}

TEST(BaseDriver, LostDriveStopsPropulsion) {
  Rig rig;
  DriveStatus lost;
  lost.online = false;
  EXPECT_CALL(*rig.drives[0], status()).WillRepeatedly(Return(lost));
  for (auto* d : rig.drives) EXPECT_CALL(*d, setCommand(speed(0.0)));
  rig.driver->setCommand({0.5, 0.0, 0.0}, 1.0);
  rig.driver->update(1.0);
  EXPECT_THAT(rig.driver->driveStopText(), testing::HasSubstr("drive0: lost"));
}

TEST(BaseDriver, NonFiniteCommandsAreRejectedAndCounted) {
  Rig rig;
  for (auto* d : rig.drives) EXPECT_CALL(*d, setCommand(speed(0.0)));
  EXPECT_FALSE(rig.driver->setCommand({std::nan(""), 0.0, 0.0}, 1.0));
  EXPECT_FALSE(rig.driver->setCommand({0.0, INFINITY, 0.0}, 1.0));
  rig.driver->update(1.0);
  EXPECT_EQ(rig.driver->rejectedCommands(), 2u);
  EXPECT_EQ(rig.driver->stopReason(), StopReason::kNoCommand);
  EXPECT_TRUE(std::isfinite(rig.driver->odometry().pose().x));
}

TEST(BaseDriver, OldCommandsTimeOut) {
  Rig rig;
  rig.driver->setCommand({0.5, 0.0, 0.0}, 1.0);
  for (auto* d : rig.drives) EXPECT_CALL(*d, setCommand(speed(2.5)));
  rig.driver->update(1.45);
  for (auto* d : rig.drives) EXPECT_CALL(*d, setCommand(speed(0.0)));
  rig.driver->update(1.55);
  EXPECT_EQ(rig.driver->stopReason(), StopReason::kCommandTimeout);
}

TEST(BaseDriver, SafetyStopHoldsUntilReleased) {
  Rig rig;
  rig.driver->setSafetyStop(true);
  rig.driver->setCommand({0.5, 0.0, 0.0}, 1.0);
  for (auto* d : rig.drives) EXPECT_CALL(*d, setCommand(speed(0.0)));
  rig.driver->update(1.0);
  EXPECT_EQ(rig.driver->stopReason(), StopReason::kSafetyStop);
  rig.driver->setSafetyStop(false);
  for (auto* d : rig.drives) EXPECT_CALL(*d, setCommand(speed(2.5)));
  rig.driver->update(1.02);
}

TEST(BaseDriver, WheelRadiusChangesAtRunTime) {
  Rig rig;
  for (auto* d : rig.drives) EXPECT_CALL(*d, reconfigure(Field(&DriveConfig::r_wheel, 0.12)));
  std::string msg;
  ASSERT_TRUE(rig.driver->setDriveParams({{-1, "r_wheel", 0.12}}, &msg)) << msg;
  for (auto* d : rig.drives) EXPECT_CALL(*d, setCommand(speed(0.5 / 0.12)));
  rig.driver->setCommand({0.5, 0.0, 0.0}, 1.0);
  rig.driver->update(1.0);
}

TEST(BaseDriver, BadParameterChangesChangeNothing) {
  Rig rig;
  for (auto* d : rig.drives) EXPECT_CALL(*d, reconfigure(_)).Times(0);
  std::string msg;
  EXPECT_FALSE(rig.driver->setDriveParams({{0, "r_wheel", 0.3}, {1, "r_wheel", -1.0}}, &msg));
  EXPECT_THAT(msg, testing::HasSubstr("r_wheel"));
  EXPECT_FALSE(rig.driver->setDriveParams({{9, "r_wheel", 0.3}}, &msg));
  EXPECT_FALSE(rig.driver->setDriveParams({{0, "node", 3}}, &msg));
  EXPECT_DOUBLE_EQ(rig.driver->config().drives[0].r_wheel, 0.2);
}

TEST(BaseDriver, HomingAndBatteries) {
  RobotConfig config = test::paperRobots()[0].config;
  std::vector<std::unique_ptr<MotorDrive>> drives;
  for (int i = 0; i < 4; ++i) {
    auto d = std::make_unique<NiceMock<MockDrive>>();
    ON_CALL(*d, feedback()).WillByDefault(Return(straight()));
    ON_CALL(*d, status()).WillByDefault(Return(DriveStatus{}));
    EXPECT_CALL(*d, startHoming()).WillOnce(Return(true));
    drives.push_back(std::move(d));
  }
  auto battery = std::make_unique<NiceMock<MockBattery>>();
  BatteryReading reading;
  reading.voltage_v = 48.5;
  EXPECT_CALL(*battery, reading()).WillRepeatedly(Return(reading));
  EXPECT_CALL(*battery, update(2.0));
  std::vector<std::unique_ptr<Battery>> batteries;
  batteries.push_back(std::move(battery));
  BaseDriver driver(config, std::make_unique<StandardCalculator>(), std::move(drives), std::move(batteries), {});
  std::string msg;
  EXPECT_TRUE(driver.homeSteering(&msg));
  driver.update(2.0);
  ASSERT_EQ(driver.batteries().size(), 1u);
  EXPECT_DOUBLE_EQ(driver.batteries()[0].voltage_v, 48.5);
}

TEST(BaseDriver, DriveCountMustMatchTheRobotFile) {
  RobotConfig config = test::paperRobots()[0].config;
  std::vector<std::unique_ptr<MotorDrive>> drives;
  drives.push_back(std::make_unique<NiceMock<MockDrive>>());
  config.source = "robots/thorvald_001.yaml";
  const size_t declared = config.drives.size();
  try {
    BaseDriver(config, std::make_unique<StandardCalculator>(), std::move(drives), {}, {});
    ADD_FAILURE() << "a drive count mismatch was accepted";
  } catch (const ConfigError& e) {
    // The message names the file and the group, and both counts.
    EXPECT_EQ(e.source(), "robots/thorvald_001.yaml");
    EXPECT_EQ(e.where(), "motor_drives");
    EXPECT_THAT(e.what(), HasSubstr("robots/thorvald_001.yaml: motor_drives: "));
    EXPECT_THAT(e.what(), HasSubstr("declares " + std::to_string(declared) + " drives"));
    EXPECT_THAT(e.what(), HasSubstr("but 1 drive devices"));
  }
}

// ---- Speed limits that keep the geometry ----
// (thorvald_bringup's speed_limits_test checks every shipped robot file the same way.)

namespace {

double norm(const Twist2D& t) { return std::sqrt(t.vx * t.vx + t.vy * t.vy + t.wz * t.wz); }

}  // namespace

TEST(SpeedLimiter, VelocityLimitScalesTheWholeTwist) {
  SpeedLimiter limiter({1.0, 0.5, 0.0, 0.0});
  const Twist2D out = limiter.limit({2.0, 0.0, 0.5}, 0.0);  // linear 2x over, angular at its limit
  EXPECT_NEAR(out.vx, 1.0, 1e-12);
  EXPECT_NEAR(out.wz, 0.25, 1e-12);  // same factor: the turning radius (vx / wz = 4 m) is kept
  const Twist2D turn = limiter.limit({0.1, 0.0, 2.0}, 0.0);
  EXPECT_NEAR(turn.wz, 0.5, 1e-12);
  EXPECT_NEAR(turn.vx, 0.025, 1e-12);
  const Twist2D free = SpeedLimiter{}.limit({100.0, -50.0, 9.0}, 0.1);  // no limits set
  EXPECT_DOUBLE_EQ(free.vx, 100.0);
  EXPECT_DOUBLE_EQ(free.wz, 9.0);
}

TEST(SpeedLimiter, AccelerationLimitApproachesAlongTheCommand) {
  SpeedLimiter limiter({0.0, 0.0, 1.0, 2.0});
  const Twist2D target{1.0, 0.5, 1.0};
  double t = 0.0;
  Twist2D out;
  while (t < 2.0 && norm(Twist2D{out.vx - target.vx, out.vy - target.vy, out.wz - target.wz}) > 1e-12) {
    out = limiter.limit(target, 0.02);
    limiter.executed(out);
    t += 0.02;
    // Every intermediate twist is a multiple of the target: the centre of rotation does not wander.
    EXPECT_NEAR(out.vy, 0.5 * out.vx, 1e-12);
    EXPECT_NEAR(out.wz, out.vx, 1e-12);
  }
  EXPECT_NEAR(t, 1.0, 0.021);  // vx and wz need 1 s at 1 m/s^2 and 2 rad/s^2 (vx binds)
  EXPECT_THROW(validateTwistLimits({-1.0, 0.0, 0.0, 0.0}, "test"), ConfigError);
  EXPECT_THROW(validateTwistLimits({0.0, NAN, 0.0, 0.0}, "test"), ConfigError);
}

TEST(SpeedLimits, BodyLimitsApplyInSimulationToo) {
  BaseDriverOptions options;
  options.limits = {1.0, 0.5, 0.0, 0.0};
  const RobotConfig config = test::paperRobots()[0].config;
  auto driver = idealDriver(config, options);
  double t = 0.0;
  performedTwist(*driver, {1000.0, 0.0, 0.0}, &t);
  EXPECT_NEAR(driver->executedTwist().vx, 1.0, 1e-9);
  for (const auto& c : driver->commands()) EXPECT_NEAR(c.wheel_speed_radps, 1.0 / 0.2, 1e-9);
  BaseDriverOptions bad;
  bad.limits.max_linear_mps = -1.0;
  EXPECT_THROW(idealDriver(config, bad), ConfigError);
}

TEST(BaseDriver, ANewCommandIsWrittenThroughAtOnce) {
  Rig rig;
  for (auto* d : rig.drives) {
    EXPECT_CALL(*d, setCommand(speed(0.0)));
    EXPECT_CALL(*d, update(1.0));
  }
  rig.driver->update(1.0);
  for (auto* d : rig.drives) {
    testing::Mock::VerifyAndClearExpectations(d);
    EXPECT_CALL(*d, setCommand(speed(2.5)));
    EXPECT_CALL(*d, update(1.005));
  }
  ASSERT_TRUE(rig.driver->setCommand({0.5, 0.0, 0.0}, 1.005));
  EXPECT_TRUE(rig.driver->writeThrough(1.005));
  // A burst faster than min_write_interval waits for the next write or cycle.
  for (auto* d : rig.drives) testing::Mock::VerifyAndClearExpectations(d);
  for (auto* d : rig.drives) EXPECT_CALL(*d, setCommand(_)).Times(0);
  ASSERT_TRUE(rig.driver->setCommand({0.3, 0.0, 0.0}, 1.006));
  EXPECT_FALSE(rig.driver->writeThrough(1.006));
  // A cycle's own write does not hold back the next write-through.
  for (auto* d : rig.drives) testing::Mock::VerifyAndClearExpectations(d);
  for (auto* d : rig.drives) EXPECT_CALL(*d, setCommand(speed(1.5))).Times(2);
  rig.driver->update(1.0075);
  ASSERT_TRUE(rig.driver->setCommand({0.3, 0.0, 0.0}, 1.0076));
  EXPECT_TRUE(rig.driver->writeThrough(1.0076));
  // The same stop checks: with the safety stop engaged a write-through sends zero.
  for (auto* d : rig.drives) testing::Mock::VerifyAndClearExpectations(d);
  rig.driver->setSafetyStop(true);
  for (auto* d : rig.drives) EXPECT_CALL(*d, setCommand(speed(0.0)));
  ASSERT_TRUE(rig.driver->setCommand({0.5, 0.0, 0.0}, 1.01));
  EXPECT_TRUE(rig.driver->writeThrough(1.01));
}

// ---- Battery policy ----

namespace {

struct BatteryRig {
  std::unique_ptr<BaseDriver> driver;
  NiceMock<MockBattery>* battery = nullptr;
  BatteryReading reading;
  std::string name = "bat0";

  explicit BatteryRig(const BatteryPolicy& policy) {
    const RobotConfig config = test::paperRobots()[0].config;
    std::vector<std::unique_ptr<MotorDrive>> drives;
    for (size_t i = 0; i < config.drives.size(); ++i) drives.push_back(std::make_unique<IdealDrive>());
    auto b = std::make_unique<NiceMock<MockBattery>>();
    battery = b.get();
    ON_CALL(*battery, name()).WillByDefault(testing::ReturnRef(name));
    ON_CALL(*battery, reading()).WillByDefault(testing::ReturnPointee(&reading));
    std::vector<std::unique_ptr<Battery>> batteries;
    batteries.push_back(std::move(b));
    BaseDriverOptions options;
    options.battery = policy;
    driver = std::make_unique<BaseDriver>(config, std::make_unique<StandardCalculator>(), std::move(drives),
                                          std::move(batteries), options);
    reading.online = true;
    reading.voltage_v = 50.0;
    reading.temperatures_c = {25.0, 26.0};
    reading.age_s = 0.0;
  }
  void cycle(double t) {
    driver->setCommand({1.0, 0.0, 0.0}, t);
    driver->update(t);
  }
};

}  // namespace

TEST(BatteryPolicy, OverTemperatureStopsByDefault) {
  BatteryRig rig(BatteryPolicy{});
  rig.cycle(1.0);
  EXPECT_EQ(rig.driver->stopReason(), StopReason::kNone);
  rig.reading.temperatures_c[1] = 71.0;
  rig.cycle(1.02);
  EXPECT_EQ(rig.driver->stopReason(), StopReason::kBatteryStop);
  EXPECT_THAT(rig.driver->batteryText(), testing::HasSubstr("bat0 over temperature (71 degC) (stop)"));
  for (const auto& c : rig.driver->commands()) EXPECT_DOUBLE_EQ(c.wheel_speed_radps, 0.0);
  rig.reading.temperatures_c[1] = 40.0;
  rig.cycle(1.04);
  EXPECT_EQ(rig.driver->stopReason(), StopReason::kNone);
}

TEST(BatteryPolicy, ALostBatteryStopsAfterItsTimeoutAndStaleValuesAreNotChecked) {
  BatteryPolicy policy;
  policy.lost_timeout_s = 1.0;
  BatteryRig rig(policy);
  rig.cycle(1.0);
  rig.reading.online = false;
  rig.reading.temperatures_c[0] = 90.0;  // stale: not acted on
  rig.reading.age_s = 0.5;
  rig.cycle(1.5);
  EXPECT_EQ(rig.driver->stopReason(), StopReason::kNone);
  rig.reading.age_s = 1.2;
  rig.cycle(2.2);
  EXPECT_EQ(rig.driver->stopReason(), StopReason::kBatteryStop);
  EXPECT_THAT(rig.driver->batteryText(), testing::HasSubstr("bat0 not heard from"));
}

TEST(BatteryPolicy, UnderVoltageCanSlowOrOnlyWarn) {
  BatteryPolicy policy;
  policy.under_voltage_v = 44.0;
  policy.under_voltage = BatteryAction::kSlow;
  policy.slow_linear_mps = 0.3;
  BatteryRig rig(policy);
  rig.reading.voltage_v = 43.0;
  rig.cycle(1.0);
  EXPECT_EQ(rig.driver->stopReason(), StopReason::kNone);
  EXPECT_TRUE(rig.driver->batterySlow());
  EXPECT_NEAR(rig.driver->executedTwist().vx, 0.3, 1e-9);
  policy.under_voltage = BatteryAction::kWarn;
  BatteryRig warn(policy);
  warn.reading.voltage_v = 43.0;
  warn.cycle(1.0);
  EXPECT_THAT(warn.driver->batteryText(), testing::HasSubstr("under voltage"));
  EXPECT_NEAR(warn.driver->executedTwist().vx, 1.0, 1e-9);
  BatteryAction a;
  EXPECT_TRUE(parseBatteryAction("slow", &a));
  EXPECT_EQ(a, BatteryAction::kSlow);
  EXPECT_FALSE(parseBatteryAction("ignore", &a));
}
