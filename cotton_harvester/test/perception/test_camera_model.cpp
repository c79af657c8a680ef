#include <cmath>

#include <gtest/gtest.h>

#include "cotton_harvester/perception/camera_model.h"

using namespace cotton_harvester::perception;

TEST(CameraModel, DefaultsAreThePapersCalibration) {
  const CameraIntrinsics k;
  EXPECT_DOUBLE_EQ(k.fx, 699.936);
  EXPECT_DOUBLE_EQ(k.fy, 699.936);
  EXPECT_DOUBLE_EQ(k.cx, 685.286);
  EXPECT_DOUBLE_EQ(k.cy, 361.248);
  EXPECT_EQ(k.width, 1280);
  EXPECT_EQ(k.height, 720);
  EXPECT_TRUE(validate(k).empty());
}

TEST(CameraModel, ProjectsWithThePinholeModel) {
  const CameraIntrinsics k;
  // A point 0.5 m right, 0.2 m up, 1.4 m deep: u = fx x / z + cx.
  const cv::Point2d p = project(k, {0.5, -0.2, 1.4});
  EXPECT_NEAR(p.x, 699.936 * 0.5 / 1.4 + 685.286, 1e-9);
  EXPECT_NEAR(p.y, 699.936 * -0.2 / 1.4 + 361.248, 1e-9);
}

TEST(CameraModel, RayModelInvertsTheProjectionFromTheRange) {
  const CameraIntrinsics k;
  for (const cv::Point3d truth : {cv::Point3d(0.5, -0.2, 1.4), cv::Point3d(-0.7, 0.4, 1.9), cv::Point3d(0, 0, 1)}) {
    const cv::Point3d back = backProject(k, project(k, truth), range(truth), DepthModel::kRay);
    EXPECT_NEAR(back.x, truth.x, 1e-9);
    EXPECT_NEAR(back.y, truth.y, 1e-9);
    EXPECT_NEAR(back.z, truth.z, 1e-9);
  }
}

TEST(CameraModel, PaperModelIsEquationsFourToSixWithThePinholeSign) {
  const CameraIntrinsics k;
  // Wz = range (eq. 6); Wx = (Ix - Cx) Wz / fx (eq. 4 with I - C); Wy likewise (eq. 5).
  const cv::Point3d p = backProject(k, {985.286, 161.248}, 2.0, DepthModel::kPaper);
  EXPECT_NEAR(p.z, 2.0, 1e-12);
  EXPECT_NEAR(p.x, 300.0 * 2.0 / 699.936, 1e-12);
  EXPECT_NEAR(p.y, -200.0 * 2.0 / 699.936, 1e-12);
  // On the optical axis both models agree.
  const cv::Point3d axis_paper = backProject(k, {k.cx, k.cy}, 1.5, DepthModel::kPaper);
  const cv::Point3d axis_ray = backProject(k, {k.cx, k.cy}, 1.5, DepthModel::kRay);
  EXPECT_NEAR(axis_paper.z, axis_ray.z, 1e-12);
}

TEST(CameraModel, RangeIsEquationSix) { EXPECT_NEAR(range({1.0, 2.0, 2.0}), 3.0, 1e-12); }

TEST(CameraModel, ParsesAndRejectsNames) {
  EXPECT_EQ(parseDepthModel("ray"), DepthModel::kRay);
  EXPECT_EQ(parseDepthModel("paper"), DepthModel::kPaper);
  EXPECT_FALSE(parseDepthModel("Ray").has_value());
  EXPECT_EQ(toString(DepthModel::kPaper), "paper");
}

TEST(CameraModel, ValidateNamesTheBadField) {
  CameraIntrinsics k;
  k.fx = 0.0;
  k.cy = NAN;
  const std::string error = validate(k);
  EXPECT_NE(error.find("fx"), std::string::npos);
  EXPECT_NE(error.find("cy"), std::string::npos);
  EXPECT_EQ(error.find("fy"), std::string::npos);
}
