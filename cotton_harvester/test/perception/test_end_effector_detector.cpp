#include <limits>

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "cotton_harvester/perception/end_effector_detector.h"

using namespace cotton_harvester::perception;

namespace {

/// Green background, an orange 60x40 block at (600, 300), an orange 6x6 speck, a red-violet block whose blue
/// (90) is above the paper's 60.
cv::Mat scene() {
  cv::Mat image(720, 1280, CV_8UC3, cv::Scalar(40, 120, 50));
  cv::rectangle(image, cv::Rect(600, 300, 60, 40), cv::Scalar(10, 120, 240), cv::FILLED);
  cv::rectangle(image, cv::Rect(100, 100, 6, 6), cv::Scalar(10, 120, 240), cv::FILLED);
  cv::rectangle(image, cv::Rect(900, 500, 80, 80), cv::Scalar(90, 40, 230), cv::FILLED);
  return image;
}

}  // namespace

TEST(EndEffectorDetector, DefaultsAreThePapersThresholds) {
  const EndEffectorParams p;
  EXPECT_EQ(p.r_min, 200);
  EXPECT_EQ(p.r_max, 255);
  EXPECT_EQ(p.g_min, 0);
  EXPECT_EQ(p.g_max, 255);
  EXPECT_EQ(p.b_min, 0);
  EXPECT_EQ(p.b_max, 60);
}

TEST(EndEffectorDetector, FindsTheOrangeBlockCentroid) {
  cv::Mat mask;
  const auto found = EndEffectorDetector(EndEffectorParams{}).detect(scene(), &mask);
  ASSERT_TRUE(found.has_value());
  // Pixels 600..659 and 300..339: centre (629.5, 319.5); contour moments are exact for a rectangle to 0.5 px.
  EXPECT_NEAR(found->pixel.x, 629.5, 0.6);
  EXPECT_NEAR(found->pixel.y, 319.5, 0.6);
  EXPECT_EQ(found->box.x, 600);
  EXPECT_EQ(found->box.width, 60);
  ASSERT_FALSE(mask.empty());
  EXPECT_EQ(mask.at<uint8_t>(320, 630), 255);
  EXPECT_EQ(mask.at<uint8_t>(103, 103), 0);  // speck below M is not part of it
  EXPECT_EQ(mask.at<uint8_t>(540, 940), 0);  // blue too high
}

TEST(EndEffectorDetector, TipIsTheMiddleOfTheFrontEdge) {
  EndEffectorParams params;
  params.point = EndEffectorPoint::kTip;
  params.tip_direction = {1.0, 0.0};
  const auto found = EndEffectorDetector(params).detect(scene());
  ASSERT_TRUE(found.has_value());
  EXPECT_NEAR(found->pixel.x, 659.0, 1.0);
  EXPECT_NEAR(found->pixel.y, 319.5, 1.0);
  params.tip_direction = {0.0, -1.0};
  const auto top = EndEffectorDetector(params).detect(scene());
  ASSERT_TRUE(top.has_value());
  EXPECT_NEAR(top->pixel.y, 300.0, 1.0);
}

TEST(EndEffectorDetector, RegionsBelowMAreDropped) {
  EndEffectorParams params;
  params.min_area_px = 60 * 40 + 100;  // larger than the block
  EXPECT_FALSE(EndEffectorDetector(params).detect(scene()).has_value());
}

TEST(EndEffectorDetector, BadImagesGiveNothing) {
  const EndEffectorDetector detector{EndEffectorParams{}};
  cv::Mat mask(4, 4, CV_8U, cv::Scalar(255));
  EXPECT_FALSE(detector.detect(cv::Mat(), &mask).has_value());
  EXPECT_TRUE(mask.empty());
  EXPECT_FALSE(detector.detect(cv::Mat(720, 1280, CV_8UC1, cv::Scalar(255))).has_value());
  EXPECT_FALSE(detector.detect(cv::Mat(720, 1280, CV_8UC3, cv::Scalar(40, 120, 50))).has_value());
}

TEST(EndEffectorDetector, RejectsBadParameters) {
  EndEffectorParams params;
  params.b_min = 80;  // above b_max 60
  EXPECT_NE(validate(params).find("b_min"), std::string::npos);
  EXPECT_THROW(EndEffectorDetector{params}, std::invalid_argument);
  params = EndEffectorParams{};
  params.min_area_px = 0;
  EXPECT_NE(validate(params).find("min_area_px"), std::string::npos);
}

TEST(EndEffectorDetector, ArmBandRunsFromTheEndEffectorToTheBorder) {
  EndEffectorObservation ee;
  ee.box = cv::Rect(600, 300, 60, 40);
  EndEffectorParams params;  // arm towards -u
  const cv::Mat band = armBandMask({1280, 720}, ee, params);
  EXPECT_EQ(band.at<uint8_t>(320, 0), 255);    // the band reaches the left border
  EXPECT_EQ(band.at<uint8_t>(320, 620), 255);  // over the end-effector's arm side
  EXPECT_EQ(band.at<uint8_t>(320, 700), 0);    // not beyond the end-effector
  EXPECT_EQ(band.at<uint8_t>(290, 300), 0);    // as wide as the box: rows 300..340
  EXPECT_EQ(band.at<uint8_t>(345, 300), 0);
  params.arm_direction = {0.0, 1.0};  // arm towards +v: band as wide as the box's width
  const cv::Mat down = armBandMask({1280, 720}, ee, params);
  EXPECT_EQ(down.at<uint8_t>(719, 630), 255);
  EXPECT_EQ(down.at<uint8_t>(719, 590), 0);
  EXPECT_EQ(down.at<uint8_t>(100, 630), 0);
  params.arm_direction = {0.0, 0.0};
  EXPECT_EQ(cv::countNonZero(armBandMask({1280, 720}, ee, params)), 0);
}

TEST(EndEffectorDetector, FoundInSunGlareWhereThePapersRgbWindowFails) {
  // Glare raises the housing's blue to 90 (paper: B <= 60); hue and saturation still say orange.
  cv::Mat image(720, 1280, CV_8UC3, cv::Scalar(40, 120, 50));
  cv::rectangle(image, cv::Rect(600, 300, 60, 40), cv::Scalar(90, 160, 250), cv::FILLED);
  cv::rectangle(image, cv::Rect(200, 500, 80, 80), cv::Scalar(70, 100, 140), cv::FILLED);  // brown soil: too grey
  const auto found = EndEffectorDetector(EndEffectorParams{}).detect(image);
  ASSERT_TRUE(found.has_value());
  EXPECT_NEAR(found->pixel.x, 629.5, 0.6);
  EndEffectorParams paper;
  paper.colour_space = EndEffectorColourSpace::kRgb;
  EXPECT_FALSE(EndEffectorDetector(paper).detect(image).has_value());
}

TEST(EndEffectorDetector, MinimumAreaScalesWithTheFocalLength) {
  EndEffectorDetector detector{EndEffectorParams{}};
  EXPECT_DOUBLE_EQ(detector.minAreaPx(), 150.0);
  detector.setFocalLength(0.5 * EndEffectorParams{}.reference_focal_px);
  EXPECT_NEAR(detector.minAreaPx(), 37.5, 1e-9);
  EXPECT_THROW(detector.setFocalLength(0.0), std::invalid_argument);
}

TEST(EndEffectorDetector, ArmMaskEndsAtTheBaseAndOnlyAtTheArmsDepth) {
  const CameraIntrinsics k;
  EndEffectorObservation ee;
  ee.box = cv::Rect(600, 300, 60, 40);
  ee.pixel = {629.5, 319.5};
  const double z = 1.5;
  const cv::Point3d position((ee.pixel.x - k.cx) / k.fx * z, (ee.pixel.y - k.cy) / k.fy * z, z);
  // Ground at 2 m; the arm at the end-effector's depth from its left edge to u = 450.
  cv::Mat cloud(720, 1280, CV_32FC3, cv::Scalar(0, 0, 2.0f));
  cloud(cv::Rect(450, 310, 180, 20)).setTo(cv::Scalar(0, 0, static_cast<float>(z)));
  cloud.at<cv::Vec3f>(320, 480) = cv::Vec3f(0, 0, std::numeric_limits<float>::quiet_NaN());
  const EndEffectorParams params;  // arm towards -u, base 0.80 m from the optical axis
  const cv::Mat mask = armMask(cloud.size(), ee, position, k, cloud, params);
  EXPECT_EQ(mask.at<uint8_t>(320, 500), 255);  // arm
  EXPECT_EQ(mask.at<uint8_t>(320, 480), 255);  // no depth inside the band: assumed arm
  EXPECT_EQ(mask.at<uint8_t>(305, 400), 0);    // in the band but at the ground's depth: a boll there stays
  // The base: 0.80 m from the axis along -x, i.e. (0.80 + x_ee) z^-1 fx pixels left of the box centre.
  const double base_u = 630.0 - (0.80 + position.x) * k.fx / z;
  cloud.setTo(cv::Scalar(0, 0, static_cast<float>(z)));
  const cv::Mat flat = armMask(cloud.size(), ee, position, k, cloud, params);
  EXPECT_EQ(flat.at<uint8_t>(320, static_cast<int>(base_u) + 3), 255);
  EXPECT_EQ(flat.at<uint8_t>(320, static_cast<int>(base_u) - 3), 0);  // beyond the arm's base
  EXPECT_EQ(flat.at<uint8_t>(320, 700), 0);                           // not on the other side
}

TEST(EndEffectorDetector, WashedOutOrangeAtFullBrightnessIsTheGlareWindow) {
  // Glare that saturates the sensor: value 255, saturation 135 (below the 150 of the main window).
  cv::Mat image(720, 1280, CV_8UC3, cv::Scalar(40, 120, 50));
  cv::rectangle(image, cv::Rect(600, 300, 60, 40), cv::Scalar(120, 200, 255), cv::FILLED);
  cv::rectangle(image, cv::Rect(200, 500, 80, 80), cv::Scalar(120, 170, 215), cv::FILLED);  // as pale, not as bright
  const auto found = EndEffectorDetector(EndEffectorParams{}).detect(image);
  ASSERT_TRUE(found.has_value());
  EXPECT_NEAR(found->pixel.x, 629.5, 0.6);
  EndEffectorParams no_glare;
  no_glare.glare_saturation_min = no_glare.saturation_min;
  EXPECT_FALSE(EndEffectorDetector(no_glare).detect(image).has_value());
}
