// FusionEkf on known trajectories: each input's update (wheel twist, IMU yaw rate and orientation, GNSS position,
// acceleration), two-D mode, the Mahalanobis gate refusing an outlier.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "thorvald_navigation/fusion_ekf.h"

namespace tn = thorvald_navigation;

namespace {

std::vector<tn::MeasuredEntry> wheelTwist(double vx, double vyaw, double var = 1e-4) {
  return {{tn::kFvx, vx, var}, {tn::kFvy, 0.0, var}, {tn::kFvyaw, vyaw, var}};
}

tn::FusionEkf planar() {
  tn::FusionEkf ekf;
  ekf.setTwoDMode(true);
  ekf.reset(tn::State15::Zero(), 0.0);
  return ekf;
}

}  // namespace

TEST(FusionEkf, StraightLineFromWheelTwist) {
  tn::FusionEkf ekf = planar();
  for (int i = 1; i <= 500; ++i) {
    ASSERT_TRUE(ekf.predict(i * 0.02));
    ASSERT_TRUE(ekf.update(wheelTwist(1.0, 0.0)).fused());
  }
  // 10 s at 1 m/s; the first step runs at the prior zero velocity (one step's worth, 0.02 m).
  EXPECT_NEAR(ekf.state()(tn::kFx), 10.0, 0.03);
  EXPECT_NEAR(ekf.state()(tn::kFy), 0.0, 1e-9);
  EXPECT_NEAR(ekf.state()(tn::kFyaw), 0.0, 1e-9);
}

TEST(FusionEkf, CircleFromWheelSpeedAndImuYawRate) {
  tn::FusionEkf ekf = planar();
  const double v = 0.5, w = 0.2, dt = 0.01;
  for (int i = 1; i <= 1000; ++i) {
    ekf.predict(i * dt);
    ASSERT_TRUE(ekf.update({{tn::kFvx, v, 1e-4}, {tn::kFvy, 0.0, 1e-4}}).fused());
    ASSERT_TRUE(ekf.update({{tn::kFvyaw, w, 1e-5}}).fused());  // the gyro
  }
  const double t = 10.0, r = v / w;
  EXPECT_NEAR(ekf.state()(tn::kFx), r * std::sin(w * t), 0.02);
  EXPECT_NEAR(ekf.state()(tn::kFy), r * (1.0 - std::cos(w * t)), 0.02);
  EXPECT_NEAR(ekf.state()(tn::kFyaw), w * t, 0.01);
}

TEST(FusionEkf, GnssPositionBoundsWheelDrift) {
  tn::FusionEkf ekf = planar();
  std::mt19937 rng(3);
  std::normal_distribution<double> gnss(0.0, 0.02);
  const double dt = 0.02;
  for (int i = 1; i <= 3000; ++i) {  // 60 s at 1 m/s; the wheels read 5 % fast
    ekf.predict(i * dt);
    ekf.update(wheelTwist(1.05, 0.0, 1e-3));
    if (i % 10 == 0) {  // 5 Hz RTK fixes of the true position
      ASSERT_TRUE(ekf.update({{tn::kFx, i * dt + gnss(rng), 4e-4}, {tn::kFy, gnss(rng), 4e-4}}).fused());
    }
  }
  EXPECT_NEAR(ekf.state()(tn::kFx), 60.0, 0.15);  // wheels alone: 63 m
  EXPECT_NEAR(ekf.state()(tn::kFy), 0.0, 0.05);
}

TEST(FusionEkf, ImuOrientationSetsYaw) {
  tn::FusionEkf ekf = planar();
  for (int i = 1; i <= 100; ++i) {
    ekf.predict(i * 0.01);
    ekf.update({{tn::kFyaw, 1.2, 1e-4}});
  }
  EXPECT_NEAR(ekf.state()(tn::kFyaw), 1.2, 1e-3);
}

TEST(FusionEkf, AccelerationIntegratesIntoSpeed) {
  tn::FusionEkf ekf = planar();
  for (int i = 1; i <= 400; ++i) {
    ekf.predict(i * 0.01);
    ekf.update({{tn::kFax, 0.5, 1e-4}});
  }
  EXPECT_NEAR(ekf.state()(tn::kFvx), 2.0, 0.05);
  EXPECT_NEAR(ekf.state()(tn::kFx), 4.0, 0.1);
}

TEST(FusionEkf, GateRefusesAPositionJumpAndKeepsTheState) {
  tn::FusionEkf ekf = planar();
  for (int i = 1; i <= 50; ++i) {
    ekf.predict(i * 0.02);
    ekf.update(wheelTwist(1.0, 0.0));
    ekf.update({{tn::kFx, i * 0.02, 1e-4}, {tn::kFy, 0.0, 1e-4}}, 5.0);
  }
  const tn::State15 before = ekf.state();
  const tn::Cov15 p_before = ekf.covariance();
  const tn::UpdateResult r = ekf.update({{tn::kFx, 11.0, 1e-4}, {tn::kFy, 0.0, 1e-4}}, 5.0);  // a 10 m jump
  EXPECT_FALSE(r.fused());
  EXPECT_TRUE(r.gated);
  EXPECT_GT(r.mahalanobis, 5.0);
  EXPECT_EQ(ekf.state(), before);
  EXPECT_EQ(ekf.covariance(), p_before);
  const tn::UpdateResult ok = ekf.update({{tn::kFx, 1.01, 1e-4}, {tn::kFy, 0.0, 1e-4}}, 5.0);
  EXPECT_TRUE(ok.fused()) << ok.error;
  EXPECT_LT(ok.mahalanobis, 5.0);
}

TEST(FusionEkf, TwoDModeHoldsThePlane) {
  tn::FusionEkf ekf = planar();
  ekf.predict(0.1);
  ASSERT_TRUE(ekf.update({{tn::kFz, 3.0, 1e-6}, {tn::kFroll, 0.3, 1e-6}, {tn::kFx, 1.0, 1e-6}}).fused());
  EXPECT_EQ(ekf.state()(tn::kFz), 0.0);
  EXPECT_EQ(ekf.state()(tn::kFroll), 0.0);
  EXPECT_NEAR(ekf.state()(tn::kFx), 1.0, 1e-3);
  // Only out-of-plane entries: nothing is left to fuse.
  EXPECT_FALSE(ekf.update({{tn::kFz, 3.0, 1e-4}}).fused());
}

TEST(FusionEkf, ThreeDModelDrivesUpASlope) {
  tn::State15 x = tn::State15::Zero();
  x(tn::kFpitch) = -0.1;  // nose up (pitch about y, REP 103)
  x(tn::kFyaw) = M_PI / 2;
  x(tn::kFvx) = 1.0;
  const tn::State15 y = tn::FusionEkf::propagate(x, 2.0);
  EXPECT_NEAR(y(tn::kFx), 0.0, 1e-9);
  EXPECT_NEAR(y(tn::kFy), 2.0 * std::cos(0.1), 1e-9);
  EXPECT_NEAR(y(tn::kFz), 2.0 * std::sin(0.1), 1e-9);
  // The Jacobian's yaw column moves the position sideways.
  tn::Cov15 f;
  tn::FusionEkf::propagate(x, 2.0, &f);
  EXPECT_NEAR(f(tn::kFx, tn::kFyaw), -2.0 * std::cos(0.1), 1e-5);
  EXPECT_NEAR(f(tn::kFx, tn::kFvx), 0.0, 1e-6);
  EXPECT_NEAR(f(tn::kFy, tn::kFvx), 2.0 * std::cos(0.1), 1e-6);
}

TEST(FusionEkf, RefusesBadInputAndTimeGoingBack) {
  tn::FusionEkf ekf = planar();
  ekf.predict(1.0);
  const tn::State15 before = ekf.state();
  EXPECT_FALSE(ekf.update({{tn::kFvx, std::nan(""), 1e-4}}).fused());
  EXPECT_FALSE(ekf.update({{tn::kFvx, 1.0, 0.0}}).fused());
  EXPECT_FALSE(ekf.update({{20, 1.0, 1e-4}}).fused());
  EXPECT_FALSE(ekf.update({}).fused());
  EXPECT_EQ(ekf.state(), before);
  EXPECT_FALSE(ekf.predict(0.5));
}
