#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "cotton_harvester/perception/boll_locator.h"

using namespace cotton_harvester::perception;

namespace {

const float kNan = std::numeric_limits<float>::quiet_NaN();

/// Organised cloud of a plane at depth z seen by the default camera.
cv::Mat planeCloud(double z) {
  const CameraIntrinsics k;
  cv::Mat cloud(k.height, k.width, CV_32FC3);
  for (int v = 0; v < k.height; ++v)
    for (int u = 0; u < k.width; ++u)
      cloud.at<cv::Vec3f>(v, u) = {float((u - k.cx) / k.fx * z), float((v - k.cy) / k.fy * z), float(z)};
  return cloud;
}

}  // namespace

TEST(BollLocator, LocatesAPointOnAPlane) {
  const CameraIntrinsics k;
  const cv::Mat cloud = planeCloud(1.5);
  const auto located = locate(cloud, {985.0, 200.0}, k, LocatorParams{});
  ASSERT_TRUE(located.has_value());
  // Expected from the pinhole model directly: x = (u - cx) z / fx.
  EXPECT_NEAR(located->position.z, 1.5, 1e-4);
  EXPECT_NEAR(located->position.x, (985.0 - k.cx) * 1.5 / k.fx, 1e-4);
  EXPECT_NEAR(located->position.y, (200.0 - k.cy) * 1.5 / k.fy, 1e-4);
  EXPECT_EQ(located->valid_points, 25);
  // The range is eq. 6 of the centre pixel's point (the window's median on a plane is close to it).
  const cv::Vec3f p = cloud.at<cv::Vec3f>(200, 985);
  EXPECT_NEAR(located->range_m, std::sqrt(p.dot(p)), 2e-3);
}

TEST(BollLocator, MedianIgnoresHolesAndAFewBackgroundPoints) {
  const CameraIntrinsics k;
  cv::Mat cloud = planeCloud(1.2);
  cloud.at<cv::Vec3f>(300, 600) = {kNan, kNan, kNan};
  cloud.at<cv::Vec3f>(301, 600) = {0.0f, 0.0f, 0.0f};                           // a zero point is no measurement either
  for (int u = 598; u <= 602; ++u) cloud.at<cv::Vec3f>(298, u) *= 2.2f / 1.2f;  // soil seen past the edge
  const auto located = locate(cloud, {600.0, 300.0}, k, LocatorParams{});
  ASSERT_TRUE(located.has_value());
  EXPECT_EQ(located->valid_points, 23);
  EXPECT_NEAR(located->position.z, 1.2, 2e-3);
}

TEST(BollLocator, TooFewValidPointsOrOutsideGivesNothing) {
  const CameraIntrinsics k;
  cv::Mat cloud = planeCloud(1.2);
  cloud(cv::Rect(598, 298, 5, 5)).setTo(cv::Scalar(kNan, kNan, kNan));
  cloud.at<cv::Vec3f>(300, 600) = {0.1f, 0.1f, 1.0f};
  cloud.at<cv::Vec3f>(300, 601) = {0.1f, 0.1f, 1.0f};
  EXPECT_FALSE(locate(cloud, {600.0, 300.0}, k, LocatorParams{}).has_value());  // 2 < 3 valid points
  LocatorParams one;
  one.min_valid_points = 2;
  EXPECT_TRUE(locate(cloud, {600.0, 300.0}, k, one).has_value());
  EXPECT_FALSE(locate(cloud, {-5.0, 300.0}, k, LocatorParams{}).has_value());
  EXPECT_FALSE(locate(cloud, {600.0, 720.0}, k, LocatorParams{}).has_value());
  EXPECT_FALSE(locate(cloud, {NAN, 300.0}, k, LocatorParams{}).has_value());
  EXPECT_FALSE(locate(cv::Mat(), {600.0, 300.0}, k, LocatorParams{}).has_value());
  EXPECT_FALSE(locate(cv::Mat(720, 1280, CV_32FC1, cv::Scalar(1)), {600.0, 300.0}, k, LocatorParams{}).has_value());
}

TEST(BollLocator, WindowAtTheImageBorderUsesWhatIsInside) {
  const CameraIntrinsics k;
  const auto located = locate(planeCloud(1.0), {0.0, 0.0}, k, LocatorParams{});
  ASSERT_TRUE(located.has_value());
  EXPECT_EQ(located->valid_points, 9);
}

TEST(BollLocator, PaperDepthModelTakesTheRangeAsDepth) {
  const CameraIntrinsics k;
  LocatorParams paper;
  paper.depth_model = DepthModel::kPaper;
  const cv::Mat cloud = planeCloud(1.5);
  const auto located = locate(cloud, {1185.286, 361.248}, k, paper);
  ASSERT_TRUE(located.has_value());
  const double range = 1.5 * std::hypot(500.0 / k.fx, 1.0);
  EXPECT_NEAR(located->position.z, range, 2e-3);  // 1.84 m, not the true 1.5 m
  EXPECT_NEAR(located->position.x, 500.0 * range / k.fx, 2e-3);
}

TEST(Reachability, DepthAndHorizontalArmLimits) {
  const ReachParams reach;  // 1.93 m, 0.70 m
  EXPECT_TRUE(isReachable({0.0, 0.0, 1.5}, reach));
  EXPECT_TRUE(isReachable({0.69, 0.5, 1.92}, reach));
  EXPECT_TRUE(isReachable({-0.70, 0.0, 1.0}, reach));
  EXPECT_FALSE(isReachable({0.71, 0.0, 1.5}, reach));
  EXPECT_FALSE(isReachable({0.0, 0.0, 1.93}, reach));
  EXPECT_FALSE(isReachable({0.0, 0.0, 0.0}, reach));
  EXPECT_FALSE(isReachable({0.0, 0.0, -1.0}, reach));
  EXPECT_FALSE(isReachable({NAN, 0.0, 1.0}, reach));
  ReachParams shifted = reach;
  shifted.arm_origin_x_m = 0.3;
  EXPECT_TRUE(isReachable({0.95, 0.0, 1.5}, shifted));
  EXPECT_FALSE(isReachable({-0.5, 0.0, 1.5}, shifted));
}

TEST(BollLocator, RejectsBadParameters) {
  LocatorParams p;
  p.window_px = 4;
  EXPECT_NE(validate(p).find("window_px"), std::string::npos);
  p = LocatorParams{};
  p.min_valid_points = 26;
  EXPECT_NE(validate(p).find("min_valid_points"), std::string::npos);
  ReachParams r;
  r.max_depth_m = -1.0;
  EXPECT_NE(validate(r).find("max_depth_m"), std::string::npos);
}

TEST(BollLocator, RegionWhoseFaceHasNoDepthIsLocatedFromItsNearestPoints) {
  // The housing's top face (60 x 60 px at 1.6 m) seen by a passive-stereo camera: no match on the uniform face but
  // along its rim (3 px); its side, a strip of 6 px, descends 8 cm from the face's edge.
  const CameraIntrinsics k;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const cv::Mat plane = planeCloud(1.6);
  cv::Mat cloud(720, 1280, CV_32FC3, cv::Scalar(nan, nan, nan));
  cv::Mat mask(720, 1280, CV_8U, cv::Scalar(0));
  const cv::Rect face(600, 300, 60, 60), side(660, 300, 6, 60);
  mask(face | side).setTo(255);
  plane(face).copyTo(cloud(face));
  cloud(cv::Rect(603, 303, 54, 54)).setTo(cv::Scalar(nan, nan, nan));
  for (int u = side.x; u < side.x + side.width; ++u)
    for (int v = side.y; v < side.y + side.height; ++v) {
      const double z = 1.6 + 0.08 * (u - side.x + 0.5) / side.width;
      cloud.at<cv::Vec3f>(v, u) = {float((u - k.cx) / k.fx * z), float((v - k.cy) / k.fy * z), float(z)};
    }
  const auto rim_and_side = locateRegion(cloud, mask, {630.0, 330.0}, k, LocatorParams{});
  ASSERT_TRUE(rim_and_side.has_value());
  EXPECT_NEAR(rim_and_side->position.z, 1.6, 2e-3);
  // Saturated in sun: the face's rim gives no depth either; its nearest points are the side's top.
  cloud(face).setTo(cv::Scalar(nan, nan, nan));
  const auto side_only = locateRegion(cloud, mask, {630.0, 330.0}, k, LocatorParams{});
  ASSERT_TRUE(side_only.has_value());
  EXPECT_NEAR(side_only->position.z, 1.6, 0.015);
  EXPECT_GT(side_only->position.z, 1.6);
}

TEST(BollLocator, RegionDepthIsTheMedianUnderItsMask) {
  const CameraIntrinsics k;
  cv::Mat cloud = planeCloud(1.6);
  // A leaf at 1.1 m covers the left third of a 60x40 region: the region keeps its own depth.
  cv::Mat leaf = planeCloud(1.1);
  leaf(cv::Rect(600, 300, 20, 40)).copyTo(cloud(cv::Rect(600, 300, 20, 40)));
  cv::Mat mask(720, 1280, CV_8U, cv::Scalar(0));
  mask(cv::Rect(600, 300, 60, 40)).setTo(255);
  const auto located = locateRegion(cloud, mask, {610.0, 320.0}, k, LocatorParams{});  // pixel on the leaf
  ASSERT_TRUE(located.has_value());
  EXPECT_NEAR(located->position.z, 1.6, 3e-3);
  EXPECT_NEAR(located->position.x, (610.0 - k.cx) / k.fx * located->position.z, 1e-9);
  // A window at that pixel would have taken the leaf's depth.
  EXPECT_NEAR(locate(cloud, {610.0, 320.0}, k, LocatorParams{})->position.z, 1.1, 3e-3);

  EXPECT_FALSE(locateRegion(cloud, cv::Mat(720, 1280, CV_8U, cv::Scalar(0)), {610.0, 320.0}, k, LocatorParams{}));
  EXPECT_FALSE(locateRegion(cloud, cv::Mat(10, 10, CV_8U, cv::Scalar(255)), {610.0, 320.0}, k, LocatorParams{}));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const cv::Mat holes(720, 1280, CV_32FC3, cv::Scalar(nan, nan, nan));
  EXPECT_FALSE(locateRegion(holes, mask, {610.0, 320.0}, k, LocatorParams{}));
}
