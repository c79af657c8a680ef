#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "greenhouse_rail_nav/line_fit.h"
#include "thorvald_base/pose2d.h"

using namespace greenhouse_rail_nav;

TEST(LineFit, RecoversNoisyLineAtAnyAngle) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.01);
  for (const double angle : {0.0, 0.3, M_PI / 2, 2.5, -1.2}) {
    const Eigen::Vector2d dir(std::cos(angle), std::sin(angle)), origin(1.0, -2.0);
    std::vector<Eigen::Vector2d> points;
    for (int i = 0; i <= 200; ++i) {
      const Eigen::Vector2d normal(-dir.y(), dir.x());
      points.push_back(origin + (i * 0.01) * dir + noise(rng) * normal);
    }
    const LineFit2D fit = fitLine(points);
    // Direction within 0.01 rad (sign free), length 2 m within 5 cm, residual close to the 1 cm noise.
    EXPECT_LT(std::acos(std::min(1.0, std::abs(fit.direction.dot(dir)))), 0.01) << angle;
    EXPECT_NEAR(fit.length(), 2.0, 0.05);
    EXPECT_NEAR(fit.rms_residual, 0.01, 0.002);
    EXPECT_GT(fit.linearity, 0.999);
    EXPECT_NEAR(fit.signedDistance(origin + dir), 0.0, 0.005);
  }
}

TEST(LineFit, BlobHasLowLinearity) {
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j) points.emplace_back(i * 0.05, j * 0.05);
  EXPECT_LT(fitLine(points).linearity, 0.1);
}

TEST(LineFit, DegenerateInput) {
  EXPECT_EQ(fitLine({}).count, 0u);
  EXPECT_EQ(fitLine({}).linearity, 0.0);
  const LineFit2D one = fitLine({Eigen::Vector2d(1, 2)});
  EXPECT_EQ(one.linearity, 0.0);
  EXPECT_EQ(one.centroid, Eigen::Vector2d(1, 2));
  const LineFit2D same = fitLine({Eigen::Vector2d(1, 2), Eigen::Vector2d(1, 2)});
  EXPECT_EQ(same.linearity, 0.0);
}

TEST(LineFit, FlipKeepsExtents) {
  LineFit2D fit = fitLine({Eigen::Vector2d(0, 0), Eigen::Vector2d(1, 0), Eigen::Vector2d(3, 0)});
  const double length = fit.length();
  const Eigen::Vector2d far_end = fit.centroid + fit.s_max * fit.direction;
  fit.flip();
  EXPECT_NEAR(fit.length(), length, 1e-12);
  EXPECT_TRUE((fit.centroid + fit.s_min * fit.direction).isApprox(far_end));
}

TEST(Pose2D, ComposeInverseAndNormalise) {
  const thorvald_base::Pose2D a(1.0, 2.0, 0.5), b(-0.3, 0.7, -2.0);
  const thorvald_base::Pose2D identity = a * a.inverse();
  EXPECT_NEAR(identity.x, 0.0, 1e-12);
  EXPECT_NEAR(identity.y, 0.0, 1e-12);
  EXPECT_NEAR(identity.yaw, 0.0, 1e-12);
  const Eigen::Vector2d p(0.4, -1.1);
  EXPECT_TRUE((a * b).transformPoint(p).isApprox(a.transformPoint(b.transformPoint(p))));
  // One convention across the workspace: thorvald_base::normalizeAngle wraps into [-pi, pi), so 3 pi lands on -pi.
  EXPECT_NEAR(thorvald_base::normalizeAngle(3 * M_PI), -M_PI, 1e-12);
  EXPECT_NEAR(thorvald_base::normalizeAngle(-3 * M_PI / 2), M_PI / 2, 1e-12);
}
