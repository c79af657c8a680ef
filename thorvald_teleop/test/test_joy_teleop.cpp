#include <gtest/gtest.h>

#include <limits>

#include "thorvald_teleop/joy_teleop.h"

using namespace thorvald_teleop;

namespace {

JoyState joy(std::vector<float> axes, std::vector<int> buttons) { return {std::move(axes), std::move(buttons)}; }

// Xbox-like: enable 4, turbo 5; left stick x/y on axes 1/0, yaw on axis 3.
JoyTeleopConfig padConfig() {
  JoyTeleopConfig c;
  c.mapping = TwistJoyMapping::defaults();
  c.mapping.enable_button = 4;
  c.mapping.enable_turbo_button = 5;
  c.mapping[TwistField::kLinearX] = {1, 0.5, 1.5};
  c.mapping[TwistField::kLinearY] = {0, 0.3, 0.6};
  c.mapping[TwistField::kAngularYaw] = {3, 0.5, 1.0};
  c.buttons.mode_drive = 0;
  c.buttons.mode_turn = 1;
  c.buttons.mode_omni = 2;
  c.buttons.priority = 3;
  c.buttons.gain_down = 6;
  c.buttons.gain_up = 7;
  c.buttons.home_steering = 9;
  c.gain = {0.5, 0.1, 1.0, 0.1};
  c.joy_timeout_s = 0.5;
  return c;
}

std::vector<int> press(std::initializer_list<int> down) {
  std::vector<int> b(11, 0);
  for (int i : down) b[static_cast<std::size_t>(i)] = 1;
  return b;
}

const std::vector<float> kSticks = {0.4f, 0.8f, 0.0f, -0.6f};  // lateral, forward, -, yaw

}  // namespace

TEST(TwistJoyMapping, DefaultsMatchTeleopTwistJoy) {
  const TwistJoyMapping m = TwistJoyMapping::defaults();
  const auto c = commandFromJoy(joy({0.25f, 0.5f}, {1}), m, false);
  EXPECT_DOUBLE_EQ(c.linear_x, 0.5 * 0.5);
  EXPECT_DOUBLE_EQ(c.angular_z, 0.25 * 0.5);
  const auto t = commandFromJoy(joy({0.25f, 0.5f}, {1}), m, true);
  EXPECT_DOUBLE_EQ(t.linear_x, 0.5 * 1.0);
  EXPECT_DOUBLE_EQ(t.angular_z, 0.25 * 0.5);
}

TEST(TwistJoyMapping, AxesBeyondTheMessageReadZero) {
  const TwistJoyMapping m = TwistJoyMapping::defaults();
  const auto c = commandFromJoy(joy({0.25f}, {}), m, false);  // axis 1 missing
  EXPECT_DOUBLE_EQ(c.linear_x, 0.0);
  EXPECT_DOUBLE_EQ(c.angular_z, 0.125);
}

TEST(JoyTeleop, NothingBeforeEnableThenOneZeroOnRelease) {
  JoyTeleop t(padConfig());
  auto a = t.onJoy(joy(kSticks, press({})), 0.0);
  ASSERT_TRUE(a.command);  // teleop_twist_joy: the first message without enable sends one stop
  EXPECT_TRUE(a.command->isZero());
  EXPECT_FALSE(t.onJoy(joy(kSticks, press({})), 0.1).command);
  a = t.onJoy(joy(kSticks, press({4})), 0.2);
  ASSERT_TRUE(a.command);
  EXPECT_DOUBLE_EQ(a.command->linear_x, 0.8f * 0.5 * 0.5);  // axis * scale * gain
  EXPECT_DOUBLE_EQ(a.command->linear_y, 0.4f * 0.3 * 0.5);  // omni (default mode) keeps lateral
  EXPECT_DOUBLE_EQ(a.command->angular_z, -0.6f * 0.5 * 0.5);
  a = t.onJoy(joy(kSticks, press({})), 0.3);
  ASSERT_TRUE(a.command);
  EXPECT_TRUE(a.command->isZero());
  EXPECT_FALSE(t.onJoy(joy(kSticks, press({})), 0.4).command);
}

TEST(JoyTeleop, NonFiniteAxesReadAsCentred) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  JoyTeleop t(padConfig());
  // Forward axis NaN: the forward component stops, the finite axes still act; never a NaN in the command.
  auto a = t.onJoy(joy({0.4f, nan, 0.0f, -0.6f}, press({4})), 0.0);
  ASSERT_TRUE(a.command);
  EXPECT_TRUE(a.non_finite_axes);
  EXPECT_DOUBLE_EQ(a.command->linear_x, 0.0);
  EXPECT_DOUBLE_EQ(a.command->linear_y, 0.4f * 0.3 * 0.5);
  EXPECT_DOUBLE_EQ(a.command->angular_z, -0.6f * 0.5 * 0.5);
  EXPECT_EQ(t.nonFiniteMessages(), 1u);
  // Every driving axis broken (infinite, NaN) with turbo held: a stop.
  a = t.onJoy(joy({-inf, inf, 0.0f, nan}, press({5})), 0.1);
  ASSERT_TRUE(a.command);
  EXPECT_TRUE(a.command->isZero());
  EXPECT_EQ(t.nonFiniteMessages(), 2u);
  // A broken axis the mapping does not use is still counted; the command is unchanged.
  a = t.onJoy(joy({0.4f, 0.8f, nan, -0.6f}, press({4})), 0.2);
  ASSERT_TRUE(a.command);
  EXPECT_DOUBLE_EQ(a.command->linear_x, 0.8f * 0.5 * 0.5);
  EXPECT_EQ(t.nonFiniteMessages(), 3u);
  // Finite messages are not counted.
  a = t.onJoy(joy(kSticks, press({4})), 0.3);
  EXPECT_FALSE(a.non_finite_axes);
  EXPECT_EQ(t.nonFiniteMessages(), 3u);
}

TEST(JoyTeleop, TurboWithoutEnable) {
  JoyTeleop t(padConfig());
  const auto a = t.onJoy(joy(kSticks, press({5})), 0.0);
  ASSERT_TRUE(a.command);
  EXPECT_DOUBLE_EQ(a.command->linear_x, 0.8f * 1.5 * 0.5);
  EXPECT_DOUBLE_EQ(a.command->angular_z, -0.6f * 1.0 * 0.5);
}

TEST(JoyTeleop, DriveModes) {
  JoyTeleop t(padConfig());
  auto a = t.onJoy(joy(kSticks, press({4, 0})), 0.0);  // A: drive
  EXPECT_TRUE(a.mode_changed);
  EXPECT_EQ(t.mode(), DriveMode::kDrive);
  EXPECT_DOUBLE_EQ(a.command->linear_y, 0.0);
  EXPECT_DOUBLE_EQ(a.command->linear_x, 0.8f * 0.5 * 0.5);
  a = t.onJoy(joy(kSticks, press({4, 1})), 0.1);  // B: turn in place
  EXPECT_EQ(t.mode(), DriveMode::kTurnInPlace);
  EXPECT_DOUBLE_EQ(a.command->linear_x, 0.0);
  EXPECT_DOUBLE_EQ(a.command->angular_z, -0.6f * 0.5 * 0.5);
  a = t.onJoy(joy(kSticks, press({4, 2})), 0.2);  // X: omni
  EXPECT_EQ(t.mode(), DriveMode::kOmni);
  EXPECT_DOUBLE_EQ(a.command->linear_y, 0.4f * 0.3 * 0.5);
}

TEST(JoyTeleop, GainStepsOnPressWithinRange) {
  JoyTeleop t(padConfig());
  t.onJoy(joy(kSticks, press({7})), 0.0);
  EXPECT_NEAR(t.gain(), 0.6, 1e-12);
  t.onJoy(joy(kSticks, press({7})), 0.1);  // held: no further step
  EXPECT_NEAR(t.gain(), 0.6, 1e-12);
  for (int i = 0; i < 10; ++i) {
    t.onJoy(joy(kSticks, press({})), 0.2 + i);
    t.onJoy(joy(kSticks, press({7})), 0.3 + i);
  }
  EXPECT_NEAR(t.gain(), 1.0, 1e-12);
  for (int i = 0; i < 20; ++i) {
    t.onJoy(joy(kSticks, press({})), 20.0 + i);
    t.onJoy(joy(kSticks, press({6})), 20.5 + i);
  }
  EXPECT_NEAR(t.gain(), 0.1, 1e-12);
  const auto a = t.onJoy(joy(kSticks, press({4, 6})), 50.0);
  EXPECT_NEAR(a.command->linear_x, 0.8f * 0.5 * 0.1, 1e-12);
}

TEST(JoyTeleop, PriorityToggles) {
  JoyTeleop t(padConfig());
  auto a = t.onJoy(joy(kSticks, press({3})), 0.0);
  ASSERT_TRUE(a.priority);
  EXPECT_TRUE(*a.priority);
  EXPECT_FALSE(t.onJoy(joy(kSticks, press({3})), 0.1).priority);  // held
  t.onJoy(joy(kSticks, press({})), 0.2);
  a = t.onJoy(joy(kSticks, press({3})), 0.3);
  ASSERT_TRUE(a.priority);
  EXPECT_FALSE(*a.priority);
}

TEST(JoyTeleop, HomeSteeringOnlyWithEnable) {
  JoyTeleop t(padConfig());
  EXPECT_FALSE(t.onJoy(joy(kSticks, press({9})), 0.0).home_steering);
  t.onJoy(joy(kSticks, press({4})), 0.1);
  EXPECT_TRUE(t.onJoy(joy(kSticks, press({4, 9})), 0.2).home_steering);
  EXPECT_FALSE(t.onJoy(joy(kSticks, press({4, 9})), 0.3).home_steering);
}

TEST(JoyTeleop, DeadmanStopsOnceWhenJoySilent) {
  JoyTeleop t(padConfig());
  EXPECT_FALSE(t.onTimer(10.0).command);  // never heard: nothing
  t.onJoy(joy(kSticks, press({4})), 1.0);
  EXPECT_FALSE(t.onTimer(1.5).command);  // exactly the timeout: not yet
  const auto a = t.onTimer(1.51);
  ASSERT_TRUE(a.command);
  EXPECT_TRUE(a.command->isZero());
  EXPECT_FALSE(t.onTimer(2.0).command);
  EXPECT_EQ(t.deadmanStops(), 1u);
  // Released pad (already stopped): silence sends nothing more.
  t.onJoy(joy(kSticks, press({})), 3.0);
  EXPECT_FALSE(t.onTimer(4.0).command);
}

TEST(JoyTeleop, Validation) {
  JoyTeleopConfig c = padConfig();
  EXPECT_EQ(validateTeleopConfig(c), "");
  c.gain.initial = 2.0;
  EXPECT_NE(validateTeleopConfig(c).find("gain is 2"), std::string::npos);
  c = padConfig();
  c.joy_timeout_s = -1.0;
  EXPECT_NE(validateTeleopConfig(c).find("joy_timeout"), std::string::npos);
  c = padConfig();
  c.mapping[TwistField::kLinearX].axis = -3;
  EXPECT_NE(validateTeleopConfig(c).find("axis for 'x'"), std::string::npos);
}
