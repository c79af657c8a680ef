#include <gmock/gmock.h>

#include <cmath>

#include "test_robots.h"
#include "thorvald_base/base_driver.h"
#include "thorvald_base/standard_calculator.h"

using namespace thorvald_base;
using testing::_;
using testing::AllOf;
using testing::Field;
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

  // The fault goes away: still stopped until cleared.
  testing::Mock::VerifyAndClearExpectations(rig.drives[2]);
  ON_CALL(*rig.drives[2], status()).WillByDefault(Return(rig.ok));
  rig.driver->setCommand({0.5, 0.0, 0.0}, 1.02);
  rig.driver->update(1.02);
  EXPECT_EQ(rig.driver->stopReason(), StopReason::kDriveStop);
  EXPECT_TRUE(rig.driver->clearDriveStop(&why));
  for (auto* d : rig.drives) EXPECT_CALL(*d, setCommand(speed(2.5)));
  rig.driver->update(1.04);
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
  EXPECT_THROW(BaseDriver(config, std::make_unique<StandardCalculator>(), std::move(drives), {}, {}), ConfigError);
}
