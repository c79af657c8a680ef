#include <algorithm>
#include <cmath>
#include <utility>

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

namespace {

/// The detection whose disc centre is nearest p, or nullptr.
const BollDetection* nearestDisc(const std::vector<BollDetection>& bolls, const cv::Point2d& p) {
  const BollDetection* best = nullptr;
  for (const BollDetection& b : bolls)
    if (!best || cv::norm(b.centre - p) < cv::norm(best->centre - p)) best = &b;
  return best;
}

/// Detects the bolls of `image` (default parameters), expects exactly two, one nearest each of `a` and `b`, and
/// returns them in that order (null where that fails).
std::pair<const BollDetection*, const BollDetection*> detectTwoNear(const cv::Mat& image, const cv::Point2d& a,
                                                                    const cv::Point2d& b,
                                                                    std::vector<BollDetection>* bolls) {
  ColourBollDetector detector{ColourBollParams{}};
  *bolls = detector.detect(image, cv::Mat());
  EXPECT_EQ(bolls->size(), 2u);
  if (bolls->size() != 2u) return {nullptr, nullptr};
  const BollDetection* near_a = nearestDisc(*bolls, a);
  const BollDetection* near_b = nearestDisc(*bolls, b);
  EXPECT_NE(near_a, near_b);
  if (near_a == near_b) return {nullptr, nullptr};
  return {near_a, near_b};
}

}  // namespace

// A small boll beside a large one, their silhouettes overlapping by 1-2 px: the closing widens the neck between them
// past split_neck_ratio of the small one's inscribed radius, so the distance transform has one maximum. The region is
// no circle: the large boll is taken out on its own circle and the small one is what remains.
TEST(ColourBollDetector, SplitsASmallBollFromALargeOneItTouches) {
  cv::Mat image(720, 1280, CV_8UC3, cv::Scalar(40, 120, 50));
  const cv::Point2d large(400, 300), small(429, 300), large2(800, 400), small2(800 + 21.9, 400 + 21.9);
  cv::circle(image, cv::Point(large), 20, kWhite, cv::FILLED);
  cv::circle(image, cv::Point(small), 11, kWhite, cv::FILLED);
  cv::circle(image, cv::Point(large2), 22, kWhite, cv::FILLED);  // the same, diagonal
  cv::circle(image, cv::Point(small2), 11, kWhite, cv::FILLED);
  ColourBollDetector detector{ColourBollParams{}};
  const std::vector<BollDetection> bolls = detector.detect(image, cv::Mat());
  ASSERT_EQ(bolls.size(), 4u);
  for (const auto& [centre, radius] : {std::pair{large, 20.0}, {small, 11.0}, {large2, 22.0}, {small2, 11.0}}) {
    const BollDetection* boll = nearestDisc(bolls, centre);
    ASSERT_NE(boll, nullptr);
    EXPECT_LT(cv::norm(boll->centre - centre), 1.5) << centre;
    EXPECT_NEAR(boll->radius_px, radius, 1.5) << centre;
    // The centroid (what is scored and located without a disc) lies on its own boll, not between the two.
    EXPECT_LT(cv::norm(boll->centroid - centre), 2.0) << centre;
  }
}

// A glint on a leaf (a thin bright line) that touches a boll joins it into one region that fails the shape tests; the
// boll is found on its own disc, the glint is left out.
TEST(ColourBollDetector, ABollJoinedToAGlintKeepsItsOwnDisc) {
  cv::Mat image(720, 1280, CV_8UC3, cv::Scalar(40, 120, 50));
  cv::circle(image, {400, 300}, 16, kWhite, cv::FILLED);
  cv::line(image, {412, 312}, {435, 335}, kWhite, 4);
  ColourBollDetector detector{ColourBollParams{}};
  const std::vector<BollDetection> bolls = detector.detect(image, cv::Mat());
  ASSERT_EQ(bolls.size(), 1u);
  EXPECT_LT(cv::norm(bolls[0].centre - cv::Point2d(400, 300)), 1.0);
  EXPECT_NEAR(bolls[0].radius_px, 16.0, 1.0);
  EXPECT_LT(cv::norm(bolls[0].centroid - cv::Point2d(400, 300)), 1.0);
  EXPECT_FALSE(bolls[0].partial);
}

// A boll partly hidden behind the one in front of it (the front boll's brown bracts between them, bridged by the
// closing): both are found, the hidden one on the circle of its own outer arc.
TEST(ColourBollDetector, ABollBehindItsNeighbourIsFoundOnItsOwnCircle) {
  cv::Mat image(720, 1280, CV_8UC3, cv::Scalar(40, 120, 50));
  const cv::Point2d front(400, 300), behind(422, 300);
  cv::circle(image, cv::Point(behind), 14, kWhite, cv::FILLED);
  cv::circle(image, cv::Point(front), 20, cv::Scalar(60, 85, 100), cv::FILLED);  // the front boll's bracts ...
  cv::circle(image, cv::Point(front), 17, kWhite, cv::FILLED);                   // ... and its lint
  std::vector<BollDetection> bolls;
  const auto [near_front, near_behind] = detectTwoNear(image, front, behind, &bolls);
  ASSERT_TRUE(near_front && near_behind);
  EXPECT_LT(cv::norm(near_front->centre - front), 1.0);
  EXPECT_NEAR(near_front->radius_px, 17.0, 1.0);
  EXPECT_LT(cv::norm(near_behind->centre - behind), 2.0);
  EXPECT_NEAR(near_behind->radius_px, 14.0, 1.5);
}

// Two touching bolls split at their neck, the second one's far half under a leaf: its part's inscribed disc lies off
// its centre, towards the neck, but the circle of the part's own outline holds it: that circle is the boll's disc
// (not the inscribed one, half the boll's radius, which the 3D test would take for a boll too small).
TEST(ColourBollDetector, ASplitPartUnderALeafKeepsTheCircleOfItsOutline) {
  cv::Mat image(720, 1280, CV_8UC3, cv::Scalar(40, 120, 50));
  const cv::Point2d first(400, 300), second(436, 300);
  cv::circle(image, cv::Point(first), 16, kWhite, cv::FILLED);
  cv::circle(image, cv::Point(second), 16, kWhite, cv::FILLED);
  cv::ellipse(image, {454, 300}, {20, 40}, 0, 0, 360, cv::Scalar(40, 150, 50), cv::FILLED);
  std::vector<BollDetection> bolls;
  const auto [whole, hidden] = detectTwoNear(image, first, second, &bolls);
  ASSERT_TRUE(whole && hidden);
  EXPECT_LT(cv::norm(whole->centre - first), 1.0);
  EXPECT_NEAR(whole->radius_px, 16.0, 1.0);
  // The visible part is a lens 14 px wide: its arcs fix the disc only roughly.
  EXPECT_LT(cv::norm(hidden->centre - second), 0.3 * 16.0);
  EXPECT_NEAR(hidden->radius_px, 16.0, 0.2 * 16.0);
}

// Half a boll past a leaf: the thick part of the half-moon holds a smaller circle than the boll's, and the region goes
// on past that circle as wide as it is (no neck): one detection, not two or three.
TEST(ColourBollDetector, HalfABollPastALeafIsNotPeeledInPieces) {
  cv::Mat image(720, 1280, CV_8UC3, cv::Scalar(40, 120, 50));
  struct HalfMoon {
    int radius, leaf_offset;  // the leaf's centre this far left of the boll's [px]
    cv::Size leaf_axes;
  };
  const HalfMoon moons[] = {{20, 10, {16, 40}}, {20, 12, {18, 36}}, {20, 14, {20, 40}}, {24, 12, {21, 36}}};
  for (int i = 0; i < 4; ++i) {
    const cv::Point centre(200 + 250 * i, 300);
    cv::circle(image, centre, moons[i].radius, kWhite, cv::FILLED);
    cv::ellipse(image, centre - cv::Point(moons[i].leaf_offset, 0), moons[i].leaf_axes, 0, 0, 360,
                cv::Scalar(40, 150, 50), cv::FILLED);
  }
  ColourBollDetector detector{ColourBollParams{}};
  const std::vector<BollDetection> bolls = detector.detect(image, cv::Mat());
  for (int i = 0; i < 4; ++i) {
    const cv::Point2d centre(200 + 250 * i, 300);
    EXPECT_LE(std::count_if(bolls.begin(), bolls.end(),
                            [&](const BollDetection& b) { return cv::norm(b.centroid - centre) < 40.0; }),
              1)
        << i;
  }
}

// The lint-coloured pixels, sixteen at a time, are those of the exact HSV test, for any thresholds and row length.
TEST(ColourBollDetector, WhitePixelsAreTheExactHsvTest) {
  cv::RNG rng(7);
  cv::Mat image(9, 1283, CV_8UC3);
  rng.fill(image, cv::RNG::UNIFORM, 0, 256);
  for (int v = 0; v < image.rows; v += 2)  // rows of near-grey pixels: saturation around every threshold
    for (int u = 0; u < image.cols; ++u) {
      const int grey = rng.uniform(0, 256);
      image.at<cv::Vec3b>(v, u) =
          cv::Vec3b(cv::saturate_cast<uint8_t>(grey), cv::saturate_cast<uint8_t>(grey - rng.uniform(0, 60)),
                    cv::saturate_cast<uint8_t>(grey + rng.uniform(-8, 8)));
    }
  for (const int saturation_max : {0, 1, 70, 128, 255})
    for (const int value_min : {0, 1, 60, 150, 255}) {
      const cv::Mat white = whitePixels(image, value_min, saturation_max);
      ASSERT_EQ(white.type(), CV_8U);
      int wrong = 0, found = 0;
      for (int v = 0; v < image.rows; ++v)
        for (int u = 0; u < image.cols; ++u) {
          const cv::Vec3b p = image.at<cv::Vec3b>(v, u);
          const int high = std::max({p[0], p[1], p[2]}), low = std::min({p[0], p[1], p[2]});
          const bool expected = high >= value_min && 255 * (high - low) <= saturation_max * high;
          const uint8_t got = white.at<uint8_t>(v, u);
          wrong += (got != 0 && got != 255) || (got == 255) != expected;
          found += expected;
        }
      EXPECT_EQ(wrong, 0) << saturation_max << " " << value_min;
      if (saturation_max == 70 && value_min == 150) {
        EXPECT_GT(found, 100);
      }
    }
  EXPECT_THROW(whitePixels(cv::Mat(4, 4, CV_8UC1, cv::Scalar(0)), 150, 70), cv::Exception);
}
