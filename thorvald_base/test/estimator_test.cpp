#include <gtest/gtest.h>

#include <cmath>

#include "thorvald_base/odometry_integrator.h"
#include "thorvald_base/velocity_estimator.h"

using namespace thorvald_base;

namespace {

/// Wheels at the corners of a 1.2 m x 1.0 m rectangle observing the rigid-body motion `t` exactly.
std::vector<WheelObservation> observe(const Twist2D& t) {
  std::vector<WheelObservation> w;
  for (double x : {-0.6, 0.6}) {
    for (double y : {-0.5, 0.5}) {
      const double vx = t.vx - t.wz * y, vy = t.vy + t.wz * x;
      w.push_back({x, y, std::atan2(vy, vx), std::hypot(vx, vy), true});
    }
  }
  return w;
}

}  // namespace

TEST(LeastSquares, ExactMotionIsRecovered) {
  LeastSquaresEstimator est;
  for (const Twist2D t :
       {Twist2D{1.0, 0.0, 0.0}, Twist2D{0.0, 0.4, 0.0}, Twist2D{0.0, 0.0, 0.314}, Twist2D{0.5, -0.2, 0.3}}) {
    const auto e = est.estimate(observe(t));
    ASSERT_TRUE(e.valid);
    EXPECT_NEAR(e.twist.vx, t.vx, 1e-9);
    EXPECT_NEAR(e.twist.vy, t.vy, 1e-9);
    EXPECT_NEAR(e.twist.wz, t.wz, 1e-9);
  }
}

TEST(LeastSquares, SlippingWheelIsDownWeighted) {
  const Twist2D t{1.0, 0.0, 0.2};
  auto wheels = observe(t);
  wheels[2].speed_mps *= 1.3;  // reads 30% faster than it rolls
  LeastSquaresEstimator robust(0.02, 5);
  LeastSquaresEstimator plain(1e9, 0);
  const auto r = robust.estimate(wheels);
  const auto p = plain.estimate(wheels);
  const double err_r = std::hypot(r.twist.vx - t.vx, r.twist.wz - t.wz);
  const double err_p = std::hypot(p.twist.vx - t.vx, p.twist.wz - t.wz);
  EXPECT_LT(err_r, 0.5 * err_p);
  EXPECT_GT(r.covariance(0, 0), 0.0);
}

TEST(LeastSquares, NoWheelsNoEstimate) {
  LeastSquaresEstimator est;
  EXPECT_FALSE(est.estimate({}).valid);
  // Only passive wheels: nothing measured moves, so the minimum-norm answer is standing still.
  const auto e = est.estimate({{0.0, 0.3, 0.0, 0.0, false}, {0.0, -0.3, 0.0, 0.0, false}});
  EXPECT_NEAR(e.twist.vx, 0.0, 1e-12);
}

TEST(RandomPairs, RecoversRotationAndTranslation) {
  RandomPairsEstimator est(7);
  auto e = est.estimate(observe({0.5, -0.2, 0.3}));
  EXPECT_NEAR(e.twist.vx, 0.5, 1e-9);
  EXPECT_NEAR(e.twist.vy, -0.2, 1e-9);
  EXPECT_NEAR(e.twist.wz, 0.3, 1e-9);
  e = est.estimate(observe({0.8, 0.1, 0.0}));  // parallel normals: translation
  EXPECT_NEAR(e.twist.vx, 0.8, 1e-9);
  EXPECT_NEAR(e.twist.vy, 0.1, 1e-9);
  EXPECT_NEAR(e.twist.wz, 0.0, 1e-12);
}

TEST(RandomPairs, SameSeedSameAnswer) {
  auto wheels = observe({0.5, 0.0, 0.3});
  wheels[1].heading_rad += 0.05;  // disagreeing wheels make the pairing matter
  RandomPairsEstimator a(3), b(3);
  EXPECT_DOUBLE_EQ(a.estimate(wheels).twist.wz, b.estimate(wheels).twist.wz);
  EXPECT_EQ(makeVelocityEstimator("nope"), nullptr);
}

TEST(Odometry, ExactArc) {
  // Half a circle of radius 1 m: v = 0.5 m/s, w = 0.5 rad/s for 2 pi s, integrated in coarse steps.
  OdometryIntegrator odom;
  const int n = 10;
  for (int i = 0; i < n; ++i) odom.integrate({0.5, 0.0, 0.5}, Eigen::Matrix3d::Identity() * 1e-4, 2.0 * M_PI / n);
  EXPECT_NEAR(odom.pose().x, 0.0, 1e-9);
  EXPECT_NEAR(odom.pose().y, 2.0, 1e-9);
  EXPECT_NEAR(std::fabs(odom.pose().yaw), M_PI, 1e-9);
  EXPECT_NEAR(odom.distance(), M_PI, 1e-9);  // path length of the half circle
  EXPECT_GT(odom.covariance()(0, 0), 0.0);
  EXPECT_GT(odom.covariance()(2, 2), 0.0);
  odom.integrate({std::nan(""), 0, 0}, Eigen::Matrix3d::Identity(), 0.1);  // ignored
  EXPECT_NEAR(odom.pose().y, 2.0, 1e-9);
  odom.reset();
  EXPECT_EQ(odom.pose().x, 0.0);
}

TEST(Odometry, CrabMove) {
  OdometryIntegrator odom;
  for (int i = 0; i < 100; ++i) odom.integrate({0.0, 0.2, 0.0}, Eigen::Matrix3d::Zero(), 0.05);
  EXPECT_NEAR(odom.pose().y, 1.0, 1e-9);
  EXPECT_NEAR(odom.pose().x, 0.0, 1e-12);
}

TEST(LeastSquaresEstimator, ReportsMotionItCannotResolve) {
  LeastSquaresEstimator ls;
  // One wheel alone: its contact point's velocity leaves rotation and translation mixed up.
  const VelocityEstimate one = ls.estimate({{0.5, 0.0, 0.3, 1.0, true}});
  EXPECT_FALSE(one.valid);
  // Two wheels at different places determine the motion.
  const VelocityEstimate two = ls.estimate({{0.5, 0.0, 0.0, 1.0, true}, {-0.5, 0.0, 0.0, 1.0, true}});
  EXPECT_TRUE(two.valid);
  EXPECT_NEAR(two.twist.vx, 1.0, 1e-9);
}
