// InputConverter: the *_config selection, IMU mounting and gravity, relative and differential inputs.
#include <cmath>

#include <gtest/gtest.h>

#include "thorvald_navigation/fusion_inputs.h"

namespace tn = thorvald_navigation;

namespace {

std::array<bool, 15> use(std::initializer_list<int> entries) {
  std::array<bool, 15> u{};
  for (int i : entries) u[static_cast<std::size_t>(i)] = true;
  return u;
}

std::vector<int> indices(const std::vector<tn::Measurement>& ms) {
  std::vector<int> out;
  for (const auto& m : ms)
    for (const auto& e : m.entries) out.push_back(e.index);
  return out;
}

double valueOf(const std::vector<tn::Measurement>& ms, int index) {
  for (const auto& m : ms)
    for (const auto& e : m.entries)
      if (e.index == index) return e.value;
  ADD_FAILURE() << "no entry " << index;
  return NAN;
}

}  // namespace

TEST(InputConverter, ConfigSelectsWhatIsFused) {
  tn::InputConfig c;
  c.use = use({tn::kFvx, tn::kFvyaw});
  tn::InputConverter conv(c);
  tn::TwistSample tw;
  tw.linear = {1.0, 0.2, 0.0};
  tw.angular = {0.0, 0.0, 0.3};
  EXPECT_EQ(indices(conv.fromTwist(tw)), (std::vector<int>{tn::kFvx, tn::kFvyaw}));
  tn::PoseSample p;
  EXPECT_TRUE(conv.fromPose(p, 0.0).empty());  // no pose entry selected
  c.use = use({tn::kFx, tn::kFy, tn::kFyaw});
  tn::InputConverter pose_conv(c);
  p.position = {3.0, 4.0, 0.0};
  p.orientation = tn::fromRollPitchYaw(0, 0, 0.7);
  const auto ms = pose_conv.fromPose(p, 0.0);
  EXPECT_EQ(indices(ms), (std::vector<int>{tn::kFx, tn::kFy, tn::kFyaw}));
  EXPECT_NEAR(valueOf(ms, tn::kFyaw), 0.7, 1e-12);
}

TEST(InputConverter, ImuMountedTurnedAndGravityRemoved) {
  tn::InputConfig c;
  c.use = use({tn::kFyaw, tn::kFvyaw, tn::kFax, tn::kFay, tn::kFaz});
  c.remove_gravity = true;
  c.mount = tn::fromRollPitchYaw(0, 0, M_PI / 2);  // IMU x axis along base_link's y
  tn::InputConverter conv(c);
  tn::ImuSample s;
  s.orientation = tn::fromRollPitchYaw(0, 0, 1.0 + M_PI / 2);  // the IMU's own heading
  s.angular_velocity = {0, 0, 0.25};
  s.linear_acceleration = {0.5, 0.0, 9.80665};  // forward along the IMU's x, gravity up
  const auto ms = conv.fromImu(s, 0.0);
  EXPECT_NEAR(valueOf(ms, tn::kFyaw), 1.0, 1e-9);
  EXPECT_NEAR(valueOf(ms, tn::kFvyaw), 0.25, 1e-12);
  EXPECT_NEAR(valueOf(ms, tn::kFax), 0.0, 1e-9);
  EXPECT_NEAR(valueOf(ms, tn::kFay), 0.5, 1e-9);
  EXPECT_NEAR(valueOf(ms, tn::kFaz), 0.0, 1e-9);
}

TEST(InputConverter, ImuWithoutOrientationGivesRatesOnly) {
  tn::InputConfig c;
  c.use = use({tn::kFyaw, tn::kFvyaw});
  tn::InputConverter conv(c);
  tn::ImuSample s;
  s.orientation_covariance(0, 0) = -1.0;  // sensor_msgs/Imu: no orientation
  EXPECT_EQ(indices(conv.fromImu(s, 0.0)), (std::vector<int>{tn::kFvyaw}));
}

TEST(InputConverter, RelativeStartsAtZero) {
  tn::InputConfig c;
  c.use = use({tn::kFx, tn::kFy, tn::kFyaw});
  c.relative = true;
  tn::InputConverter conv(c);
  tn::PoseSample p;
  p.position = {5.0, 5.0, 0.0};
  p.orientation = tn::fromRollPitchYaw(0, 0, M_PI / 2);
  auto ms = conv.fromPose(p, 0.0);
  EXPECT_NEAR(valueOf(ms, tn::kFx), 0.0, 1e-12);
  EXPECT_NEAR(valueOf(ms, tn::kFyaw), 0.0, 1e-12);
  p.position = {5.0, 7.0, 0.0};  // 2 m along the first pose's heading
  ms = conv.fromPose(p, 1.0);
  EXPECT_NEAR(valueOf(ms, tn::kFx), 2.0, 1e-12);
  EXPECT_NEAR(valueOf(ms, tn::kFy), 0.0, 1e-12);
}

TEST(InputConverter, DifferentialGivesBodyVelocities) {
  tn::InputConfig c;
  c.use = use({tn::kFx, tn::kFy, tn::kFyaw});
  c.differential = true;
  tn::InputConverter conv(c);
  tn::PoseSample p;
  p.orientation = tn::fromRollPitchYaw(0, 0, M_PI / 2);
  p.covariance = tn::Matrix6::Identity() * 0.01;
  EXPECT_TRUE(conv.fromPose(p, 0.0).empty());  // the first message only starts the difference
  p.position = {0.0, 0.1, 0.0};                // 0.1 m ahead (north, heading north) in 0.1 s, turning 0.05 rad
  p.orientation = tn::fromRollPitchYaw(0, 0, M_PI / 2 + 0.05);
  const auto ms = conv.fromPose(p, 0.1);
  EXPECT_EQ(indices(ms), (std::vector<int>{tn::kFvx, tn::kFvy, tn::kFvyaw}));
  EXPECT_NEAR(valueOf(ms, tn::kFvx), 1.0, 1e-9);
  EXPECT_NEAR(valueOf(ms, tn::kFvy), 0.0, 1e-9);
  EXPECT_NEAR(valueOf(ms, tn::kFvyaw), 0.5, 1e-9);
  EXPECT_NEAR(ms[0].entries[0].variance, 0.02 / 0.01, 1e-9);
}
