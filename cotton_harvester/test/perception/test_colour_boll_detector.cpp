#include <algorithm>

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "cotton_harvester/perception/colour_boll_detector.h"

using namespace cotton_harvester::perception;

namespace {

const cv::Scalar kWhite(235, 238, 240);

bool hasDetectionNear(const std::vector<BollDetection>& bolls, const cv::Point2d& p, double tolerance) {
  return std::any_of(bolls.begin(), bolls.end(), [&](const BollDetection& b) {
    return std::hypot(b.centroid.x - p.x, b.centroid.y - p.y) <= tolerance;
  });
}

}  // namespace

TEST(ColourBollDetector, FindsWhiteCompactBollsOnly) {
  cv::Mat image(720, 1280, CV_8UC3, cv::Scalar(40, 120, 50));
  cv::circle(image, {300, 200}, 15, kWhite, cv::FILLED);                      // boll
  cv::circle(image, {800, 500}, 22, kWhite, cv::FILLED);                      // boll
  cv::rectangle(image, cv::Rect(100, 600, 300, 20), kWhite, cv::FILLED);      // aluminium bar
  cv::circle(image, {1000, 100}, 4, kWhite, cv::FILLED);                      // glint
  cv::circle(image, {600, 300}, 18, cv::Scalar(40, 230, 240), cv::FILLED);    // yellow: saturated
  cv::circle(image, {1100, 300}, 18, cv::Scalar(110, 110, 110), cv::FILLED);  // grey: too dark
  ColourBollDetector detector{ColourBollParams{}};
  const std::vector<BollDetection> bolls = detector.detect(image, cv::Mat());
  ASSERT_EQ(bolls.size(), 2u);
  EXPECT_TRUE(hasDetectionNear(bolls, {300, 200}, 0.5));
  EXPECT_TRUE(hasDetectionNear(bolls, {800, 500}, 0.5));
  for (const BollDetection& b : bolls) {
    EXPECT_GT(b.confidence, 0.5);
    EXPECT_LE(b.confidence, 1.0);
    EXPECT_TRUE(b.box.contains(b.centroid));
  }
}

TEST(ColourBollDetector, ExclusionMaskHidesTheEndEffectorRegion) {
  cv::Mat image(720, 1280, CV_8UC3, cv::Scalar(40, 120, 50));
  cv::circle(image, {300, 200}, 15, kWhite, cv::FILLED);
  cv::circle(image, {800, 500}, 15, kWhite, cv::FILLED);
  cv::Mat exclude(image.size(), CV_8U, cv::Scalar(0));
  cv::rectangle(exclude, cv::Rect(250, 150, 100, 100), cv::Scalar(255), cv::FILLED);
  ColourBollDetector detector{ColourBollParams{}};
  const std::vector<BollDetection> bolls = detector.detect(image, exclude);
  ASSERT_EQ(bolls.size(), 1u);
  EXPECT_TRUE(hasDetectionNear(bolls, {800, 500}, 0.5));
}

TEST(ColourBollDetector, BadInputGivesNothing) {
  ColourBollDetector detector{ColourBollParams{}};
  EXPECT_TRUE(detector.detect(cv::Mat(), cv::Mat()).empty());
  EXPECT_TRUE(detector.detect(cv::Mat(10, 10, CV_32FC3, cv::Scalar(1, 1, 1)), cv::Mat()).empty());
  // A mask of the wrong size is ignored rather than trusted.
  cv::Mat image(100, 100, CV_8UC3, cv::Scalar(40, 120, 50));
  cv::circle(image, {50, 50}, 15, kWhite, cv::FILLED);
  EXPECT_EQ(detector.detect(image, cv::Mat(10, 10, CV_8U, cv::Scalar(255))).size(), 1u);
}

TEST(ColourBollDetector, RejectsBadParameters) {
  ColourBollParams params;
  params.min_visible_fraction = 0.0;
  EXPECT_NE(validate(params).find("min_visible_fraction"), std::string::npos);
  EXPECT_THROW(ColourBollDetector{params}, std::invalid_argument);
  params = ColourBollParams{};
  params.max_aspect_ratio = 0.5;
  EXPECT_NE(validate(params).find("max_aspect_ratio"), std::string::npos);
}

TEST(ColourBollDetector, SplitsTouchingBolls) {
  cv::Mat image(720, 1280, CV_8UC3, cv::Scalar(40, 120, 50));
  // Two bolls of radius 15 px whose silhouettes overlap by 2 px, and a pair of different sizes side by side.
  cv::circle(image, {400, 300}, 15, kWhite, cv::FILLED);
  cv::circle(image, {428, 300}, 15, kWhite, cv::FILLED);
  cv::circle(image, {800, 400}, 20, kWhite, cv::FILLED);
  cv::circle(image, {822, 428}, 14, kWhite, cv::FILLED);
  ColourBollDetector detector{ColourBollParams{}};
  const std::vector<BollDetection> bolls = detector.detect(image, cv::Mat());
  ASSERT_EQ(bolls.size(), 4u);
  // Each part's centroid lies within a few pixels of its disc's centre (the cut is straight, not the arc).
  EXPECT_TRUE(hasDetectionNear(bolls, {400, 300}, 3.0));
  EXPECT_TRUE(hasDetectionNear(bolls, {428, 300}, 3.0));
  EXPECT_TRUE(hasDetectionNear(bolls, {800, 400}, 3.0));
  EXPECT_TRUE(hasDetectionNear(bolls, {822, 428}, 3.0));
}

TEST(ColourBollDetector, OneBollCutByATwigStaysOne) {
  cv::Mat image(720, 1280, CV_8UC3, cv::Scalar(40, 120, 50));
  cv::circle(image, {400, 300}, 16, kWhite, cv::FILLED);
  cv::line(image, {370, 290}, {430, 310}, cv::Scalar(60, 85, 100), 3);  // a brown twig across it
  ColourBollDetector detector{ColourBollParams{}};
  const std::vector<BollDetection> bolls = detector.detect(image, cv::Mat());
  ASSERT_EQ(bolls.size(), 1u);
  EXPECT_TRUE(hasDetectionNear(bolls, {400, 300}, 2.0));
}

TEST(ColourBollDetector, SizeThresholdsFollowTheImageSize) {
  // A boll of radius 4 px: the smallest boll at 640x360 (about 3.4 px), a speck at 1280x720 (about 6.8 px).
  cv::Mat small(360, 640, CV_8UC3, cv::Scalar(40, 120, 50));
  cv::circle(small, {300, 200}, 4, kWhite, cv::FILLED);
  ColourBollDetector detector{ColourBollParams{}};
  EXPECT_TRUE(detector.detect(small, cv::Mat()).empty());
  detector.setGeometry(scaledTo(CameraIntrinsics{}, 640, 360), BollGeometry{});
  EXPECT_NEAR(detector.scale().radius_min_px, 0.5 * ColourBollDetector{ColourBollParams{}}.scale().radius_min_px, 1e-9);
  const std::vector<BollDetection> bolls = detector.detect(small, cv::Mat());
  ASSERT_EQ(bolls.size(), 1u);
  EXPECT_TRUE(hasDetectionNear(bolls, {300, 200}, 1.0));
  // A higher camera sees smaller bolls: the thresholds shrink with it.
  BollGeometry high;
  high.camera_height_m = 3.0;
  detector.setGeometry(CameraIntrinsics{}, high);
  EXPECT_LT(detector.scale().min_area_px, ColourBollDetector{ColourBollParams{}}.scale().min_area_px);
}

TEST(ColourBollDetector, DarkerExposureLowersTheValueThreshold) {
  // The whole frame at 60% exposure: bolls at value ~143, under the bright-scene threshold of 150.
  cv::Mat image(720, 1280, CV_8UC3, cv::Scalar(24, 72, 30));
  cv::circle(image, {300, 200}, 15, cv::Scalar(141, 143, 144), cv::FILLED);
  ColourBollDetector detector{ColourBollParams{}};
  EXPECT_EQ(detector.detect(image, cv::Mat()).size(), 1u);
}

TEST(ColourBollDetector, ACrescentPastALeafIsAPartialBollOnlyWhenAsked) {
  cv::Mat image(720, 1280, CV_8UC3, cv::Scalar(40, 120, 50));
  cv::circle(image, {400, 300}, 24, kWhite, cv::FILLED);                                     // a boll ...
  cv::ellipse(image, {412, 300}, {30, 40}, 0, 0, 360, cv::Scalar(40, 150, 50), cv::FILLED);  // ... a leaf over it
  cv::circle(image, {900, 300}, 24, kWhite, cv::FILLED);                                     // a whole boll
  cv::rectangle(image, cv::Rect(100, 600, 300, 20), kWhite, cv::FILLED);                     // aluminium bar
  ColourBollDetector plain{ColourBollParams{}};
  const std::vector<BollDetection> whole_only = plain.detect(image, cv::Mat());
  ASSERT_EQ(whole_only.size(), 1u);
  EXPECT_FALSE(whole_only[0].partial);
  EXPECT_TRUE(hasDetectionNear(whole_only, {900, 300}, 0.5));

  ColourBollParams params;
  params.partial_min_fraction = 0.6;
  ColourBollDetector with_partial{params};
  const std::vector<BollDetection> bolls = with_partial.detect(image, cv::Mat());
  const auto crescent = std::find_if(bolls.begin(), bolls.end(), [](const BollDetection& b) { return b.partial; });
  ASSERT_NE(crescent, bolls.end());
  // The crescent's centroid lies on the visible side, inside the boll's disc, left of its centre.
  EXPECT_LT(crescent->centroid.x, 400.0 - 5.0);
  EXPECT_LT(std::hypot(crescent->centroid.x - 400.0, crescent->centroid.y - 300.0), 24.0);
  EXPECT_LT(crescent->confidence, 0.31);
  EXPECT_TRUE(hasDetectionNear(bolls, {900, 300}, 0.5));
  // The bar is larger than any boll: neither whole nor partial.
  EXPECT_FALSE(hasDetectionNear(bolls, {250, 610}, 40.0));
  params.partial_min_fraction = 1.5;
  EXPECT_THROW(ColourBollDetector{params}, std::invalid_argument);
}
