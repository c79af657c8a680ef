#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "thorvald_navigation/planar_ekf.h"

namespace tn = thorvald_navigation;

namespace {

const std::array<bool, 6> kTwistMask{false, false, false, true, true, true};
const std::array<bool, 6> kYawRateMask{false, false, false, false, false, true};
const std::array<bool, 6> kYawMask{false, false, true, false, false, false};

tn::State6 twist(double vx, double vy, double wz) {
  tn::State6 z = tn::State6::Zero();
  z(tn::kVx) = vx;
  z(tn::kVy) = vy;
  z(tn::kVyaw) = wz;
  return z;
}

TEST(PlanarEkf, IntegratesAConstantTwistAlongAnArc) {
  tn::PlanarEkf ekf;
  ekf.reset({}, 0.0);
  const double v = 0.5, w = 0.2, dt = 0.02;
  for (int i = 1; i <= 500; ++i) {
    ekf.predict(i * dt);
    ASSERT_EQ(ekf.update(twist(v, 0.0, w), tn::State6::Constant(1e-4), kTwistMask), "");
  }
  // Exact arc after 10 s (the first step runs at the prior zero velocity: allow a step's worth).
  const double t = 10.0, r = v / w;
  EXPECT_NEAR(ekf.pose().x, r * std::sin(w * t), 0.02);
  EXPECT_NEAR(ekf.pose().y, r * (1.0 - std::cos(w * t)), 0.02);
  EXPECT_NEAR(ekf.pose().yaw, w * t, 0.01);
}

TEST(PlanarEkf, GyroCorrectsABiasedWheelYawRate) {
  tn::PlanarEkf ekf;
  ekf.reset({}, 0.0);
  std::mt19937 rng(7);
  std::normal_distribution<double> gyro_noise(0.0, 0.005);
  const double dt = 0.01;
  for (int i = 1; i <= 2000; ++i) {  // 20 s straight; wheels think the robot turns at 0.02 rad/s
    ekf.predict(i * dt);
    tn::State6 var = tn::State6::Constant(1.0);
    var(tn::kVx) = var(tn::kVy) = 1e-4;
    var(tn::kVyaw) = 0.01;  // wheel yaw rate is poor (slip of the casters)
    ekf.update(twist(0.5, 0.0, 0.02), var, kTwistMask);
    tn::State6 g = tn::State6::Zero();
    g(tn::kVyaw) = gyro_noise(rng);
    ekf.update(g, tn::State6::Constant(1e-5), kYawRateMask);
  }
  const double yaw_wheel_only = 0.02 * 20.0;
  EXPECT_LT(std::abs(ekf.pose().yaw), 0.1 * yaw_wheel_only);
  EXPECT_NEAR(ekf.pose().x, 10.0, 0.05);
  EXPECT_LT(std::abs(ekf.pose().y), 0.05);
}

// Wheels that slip or push against something report a turn the gyro does not feel: for 2 s of a straight 20 s drive
// (from rest, 0.5 m/s^2 up to 0.5 m/s) the wheel odometry says 0.3 rad/s. Behind a 5 sigma gate (odom_fusion's
// odom0_twist_rejection_threshold) those twists are refused and the heading holds; without one the filter takes part of
// the false turn.
double headingAfterAFalseWheelTurn(double gate_sigma, int* gated, int* gated_while_true) {
  tn::PlanarEkf ekf;
  ekf.reset({}, 0.0);
  std::mt19937 rng(3);
  std::normal_distribution<double> gyro_noise(0.0, 0.003);
  const double dt = 0.01;
  *gated = *gated_while_true = 0;
  for (int i = 1; i <= 2000; ++i) {
    ekf.predict(i * dt);
    const bool slipping = i > 1000 && i <= 1200;
    tn::State6 var = tn::State6::Constant(1.0);
    var(tn::kVx) = var(tn::kVy) = var(tn::kVyaw) = 1e-4;
    const double v = std::min(0.5, 0.5 * i * dt);
    const tn::UpdateResult r = ekf.update(twist(v, 0.0, slipping ? 0.3 : 0.0), var, kTwistMask, gate_sigma);
    *(slipping ? gated : gated_while_true) += r.gated;
    EXPECT_TRUE(r.fused() || r.gated) << r.error;
    tn::State6 g = tn::State6::Zero();
    g(tn::kVyaw) = gyro_noise(rng);
    ekf.update(g, tn::State6::Constant(1e-5), kYawRateMask);
  }
  return ekf.pose().yaw;
}

TEST(PlanarEkf, AGateRefusesTheTwistOfSlippingWheels) {
  int gated = 0, gated_true = 0, gated_none = 0, gated_none_true = 0;
  const double with_gate = headingAfterAFalseWheelTurn(5.0, &gated, &gated_true);
  const double without =
      headingAfterAFalseWheelTurn(std::numeric_limits<double>::infinity(), &gated_none, &gated_none_true);
  EXPECT_LT(std::abs(with_gate), 0.01);
  EXPECT_GT(std::abs(without), 3.0 * std::abs(with_gate) + 0.02)
      << "the false turn does reach the filter without a gate";
  EXPECT_GE(gated, 150);  // most of the 200 slipping twists
  EXPECT_EQ(gated_true, 0);
  EXPECT_EQ(gated_none + gated_none_true, 0);
}

TEST(PlanarEkf, AbsoluteYawWrapsAroundPi) {
  tn::PlanarEkf ekf;
  ekf.reset({0, 0, 3.1}, 0.0);
  tn::State6 z = tn::State6::Zero();
  z(tn::kYaw) = -3.1;  // 0.083 rad away across the wrap
  for (int i = 1; i <= 50; ++i) {
    ekf.predict(i * 0.01);
    ekf.update(z, tn::State6::Constant(1e-4), kYawMask);
  }
  EXPECT_NEAR(std::abs(ekf.pose().yaw), 3.1, 0.01);
  EXPECT_LT(ekf.pose().yaw, 0.0);
}

TEST(PlanarEkf, RejectsBadMeasurementsAndTimeGoingBack) {
  tn::PlanarEkf ekf;
  ekf.reset({1, 2, 0.5}, 5.0);
  const tn::State6 before = ekf.state();
  EXPECT_NE(ekf.update(twist(std::nan(""), 0, 0), tn::State6::Constant(1e-4), kTwistMask), "");
  EXPECT_NE(ekf.update(twist(1, 0, 0), tn::State6::Constant(0.0), kTwistMask), "");
  EXPECT_NE(ekf.update(twist(1, 0, 0), tn::State6::Constant(1e-4), {}), "");
  EXPECT_EQ(ekf.state(), before);
  EXPECT_FALSE(ekf.predict(4.0));
  EXPECT_TRUE(ekf.predict(5.5));
  // Uncertainty grows without measurements, and stays symmetric.
  const tn::Cov6 p = ekf.covariance();
  EXPECT_GT(p(tn::kX, tn::kX), 0.0);
  EXPECT_NEAR((p - p.transpose()).norm(), 0.0, 1e-12);
}

}  // namespace
