// The colour boll detector's stages one by one: the region and its peaks, shape, circles, split, peeling, scores.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include <opencv2/imgproc.hpp>

#include "cotton_harvester/perception/boll_circle_fit.h"
#include "cotton_harvester/perception/boll_peeling.h"
#include "cotton_harvester/perception/boll_region.h"
#include "cotton_harvester/perception/boll_shape.h"
#include "cotton_harvester/perception/colour_boll_params.h"
#include "cotton_harvester/perception/touching_bolls.h"

using namespace cotton_harvester::perception;

namespace {

/// The largest external contour of a CV_8U mask.
std::vector<cv::Point> outlineOf(const cv::Mat& mask) {
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mask.clone(), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  std::vector<cv::Point> largest;
  for (const auto& c : contours)
    if (c.size() > largest.size()) largest = c;
  return largest;
}

cv::Mat blank() { return cv::Mat::zeros(200, 300, CV_8U); }

/// Two discs of radius 20 px, centres 40 px apart along a row, touching.
cv::Mat twoTouchingDiscs() {
  cv::Mat mask = blank();
  cv::circle(mask, {100, 100}, 20, cv::Scalar(255), cv::FILLED);
  cv::circle(mask, {140, 100}, 20, cv::Scalar(255), cv::FILLED);
  return mask;
}

/// A disc of radius 20 px at (100, 100) with a bar `width` px wide running 40 px to its right.
cv::Mat discWithBar(int width) {
  cv::Mat mask = blank();
  cv::circle(mask, {100, 100}, 20, cv::Scalar(255), cv::FILLED);
  cv::rectangle(mask, cv::Rect(100, 100 - width / 2, 80, width), cv::Scalar(255), cv::FILLED);
  return mask;
}

BollCircleLimits limits() {
  BollCircleLimits l;
  l.radius_min_px = 10.0;
  l.radius_max_px = 30.0;
  return l;
}

BollRegion regionOf(const cv::Mat& mask) {
  const cv::Mat bgr(mask.size(), CV_8UC3, cv::Scalar(200, 220, 230));
  return cutBollRegion(outlineOf(mask), bgr, mask, 10.0);
}

}  // namespace

TEST(BollRegion, CutsTheRegionWithAMarginAndItsBrightness) {
  cv::Mat mask = blank();
  cv::circle(mask, {100, 80}, 20, cv::Scalar(255), cv::FILLED);
  const BollRegion region = regionOf(mask);
  EXPECT_EQ(region.box, cv::Rect(80, 60, 41, 41));
  EXPECT_NEAR(region.brightness, 230.0 / 255.0, 1e-9);
  EXPECT_EQ(region.pad, 2 * static_cast<int>(0.35 * 10.0) + 1 + 1);
  EXPECT_EQ(region.origin, cv::Point(80 - region.pad, 60 - region.pad));
  EXPECT_EQ(region.pixels.size(), cv::Size(41 + 2 * region.pad, 41 + 2 * region.pad));
  EXPECT_EQ(cv::countNonZero(region.pixels), cv::countNonZero(mask));
  double max_dist = 0.0;
  cv::Point at;
  cv::minMaxLoc(region.dist, nullptr, &max_dist, nullptr, &at);
  EXPECT_NEAR(max_dist, 20.5, 1.0);  // the inscribed radius
  EXPECT_LE(cv::norm(at + region.origin - cv::Point(100, 80)), 1.5);
}

TEST(BollRegion, PeaksSeparateTouchingBollsButNotTheLobesOfOne) {
  const BollRegion two = regionOf(twoTouchingDiscs());
  const auto peaks = findBollPeaks(two.dist, 4.0, 0.75, 11);
  ASSERT_EQ(peaks.size(), 2u);
  EXPECT_NEAR(std::abs(peaks[0].centre.x - peaks[1].centre.x), 40.0, 3.0);
  EXPECT_LT(neckBetween(two.dist, peaks[0].centre, peaks[1].centre), 0.75 * std::min(peaks[0].radius, peaks[1].radius));

  cv::Mat lobes = blank();  // one boll with two lobes: the centres 12 px apart
  cv::circle(lobes, {100, 100}, 20, cv::Scalar(255), cv::FILLED);
  cv::circle(lobes, {112, 100}, 20, cv::Scalar(255), cv::FILLED);
  EXPECT_EQ(findBollPeaks(regionOf(lobes).dist, 4.0, 0.75, 11).size(), 1u);
  EXPECT_TRUE(findBollPeaks(regionOf(lobes).dist, 40.0, 0.75, 11).empty());  // nothing that deep
}

TEST(BollShape, MeasuresARoundBollAndABar) {
  cv::Mat disc = blank();
  cv::circle(disc, {100, 100}, 20, cv::Scalar(255), cv::FILLED);
  const auto round_outline = outlineOf(disc);
  const RegionShape round = measureRegionShape(round_outline, cv::contourArea(round_outline));
  EXPECT_GT(round.circularity, 0.85);
  EXPECT_GT(round.solidity, 0.95);
  EXPECT_NEAR(round.aspect, 1.0, 0.05);
  EXPECT_TRUE(wholeBollShape(round, 0.45, 0.80, 2.5));

  cv::Mat bar = blank();
  cv::rectangle(bar, cv::Rect(20, 20, 100, 10), cv::Scalar(255), cv::FILLED);
  const auto bar_outline = outlineOf(bar);
  const RegionShape long_bar = measureRegionShape(bar_outline, cv::contourArea(bar_outline));
  EXPECT_GT(long_bar.aspect, 8.0);
  EXPECT_FALSE(wholeBollShape(long_bar, 0.45, 0.80, 2.5));
}

TEST(BollShape, Confidences) {
  RegionShape shape;
  shape.circularity = 0.9;
  shape.solidity = 0.8;
  EXPECT_DOUBLE_EQ(wholeBollConfidence(shape, 0.5), 0.9 * 0.8 * 0.5);
  EXPECT_DOUBLE_EQ(glimpseConfidence(shape, 0.5), 0.9 * 0.8 * 0.5 * 0.3);
  EXPECT_DOUBLE_EQ(discCoverConfidence(0.6, 0.5), 0.3);
  EXPECT_DOUBLE_EQ(discCoverConfidence(1.2, 1.0), 1.0);  // clamped
  EXPECT_DOUBLE_EQ(discCoverConfidence(-0.1, 1.0), 0.0);
}

TEST(BollCircleFit, RoundOutlinesOfABollsSizeOnly) {
  cv::Mat disc = blank();
  cv::circle(disc, {100, 100}, 15, cv::Scalar(255), cv::FILLED);
  const auto circle = roundOutline(outlineOf(disc), limits());
  ASSERT_TRUE(circle);
  EXPECT_NEAR(circle->centre.x, 100.0, 0.5);
  EXPECT_NEAR(circle->centre.y, 100.0, 0.5);
  EXPECT_NEAR(circle->radius_px, 15.5, 0.7);
  EXPECT_TRUE(holdsDisc(*circle, {100.0, 100.0}, 15.0));
  EXPECT_FALSE(holdsDisc(*circle, {110.0, 100.0}, 15.0));

  cv::Mat big = blank();
  cv::circle(big, {150, 100}, 60, cv::Scalar(255), cv::FILLED);  // larger than 1.2 x the largest boll
  EXPECT_FALSE(roundOutline(outlineOf(big), limits()));
  cv::Mat bar = blank();
  cv::rectangle(bar, cv::Rect(20, 20, 100, 10), cv::Scalar(255), cv::FILLED);
  EXPECT_FALSE(roundOutline(outlineOf(bar), limits()));
}

TEST(BollCircleFit, LobeCircleOfABollJoinedToABar) {
  const auto outline = outlineOf(discWithBar(6));
  EXPECT_FALSE(roundOutline(outline, limits()));  // the whole region is no circle
  const auto circle = lobeCircle(outline, {100.0, 100.0}, 19.0, limits());
  ASSERT_TRUE(circle);
  EXPECT_NEAR(circle->centre.x, 100.0, 1.0);
  EXPECT_NEAR(circle->centre.y, 100.0, 1.0);
  EXPECT_NEAR(circle->radius_px, 20.5, 1.0);
  EXPECT_FALSE(lobeCircle(outline, {160.0, 100.0}, 3.0, limits()));  // on the bar: no round outline around it
}

TEST(TouchingBolls, EachPixelGoesToTheNearestPeakAndEachPartIsABoll) {
  const BollRegion region = regionOf(twoTouchingDiscs());
  const auto peaks = findBollPeaks(region.dist, 4.0, 0.75, 11);
  ASSERT_EQ(peaks.size(), 2u);
  cv::Mat owner;
  const std::vector<BollPart> parts = assignToPeaks(region, peaks, &owner);
  ASSERT_EQ(parts.size(), 2u);
  EXPECT_EQ(parts[0].count + parts[1].count, cv::countNonZero(region.pixels));
  EXPECT_NEAR(parts[0].count, parts[1].count, 0.1 * parts[0].count);
  EXPECT_EQ(cv::countNonZero(owner), cv::countNonZero(region.pixels));

  TouchingBollLimits split;
  split.min_area_px = 100.0;
  split.max_single_area_px = 3000.0;
  split.visible_share_min = kWholeWhiteShare;
  split.circle = limits();
  const auto bolls = splitTouchingBolls(region, peaks, split);
  ASSERT_EQ(bolls.size(), 2u);
  for (const BollDetection& boll : bolls) {
    const double x = boll.centre.x < 120.0 ? 100.0 : 140.0;
    EXPECT_NEAR(boll.centre.x, x, 2.0);
    EXPECT_NEAR(boll.centre.y, 100.0, 2.0);
    EXPECT_NEAR(boll.radius_px, 20.5, 2.0);
    EXPECT_NEAR(boll.confidence, region.brightness, 0.1);
    EXPECT_FALSE(boll.outline.empty());
  }
  split.max_single_area_px = 500.0;  // parts larger than a boll are dropped
  EXPECT_TRUE(splitTouchingBolls(region, peaks, split).empty());
}

TEST(BollPeeling, ABollJoinedThroughANeckIsTakenOutAndTheRestRemains) {
  BollCircle circle;
  circle.centre = {100.0, 100.0};
  circle.radius_px = 20.5;
  const cv::Point origin(0, 0);
  const cv::Mat thin = discWithBar(6), wide = discWithBar(36);
  EXPECT_NEAR(rimCrossingHalfWidth(thin, origin, circle), 3.0, 1.5);
  EXPECT_GT(rimCrossingHalfWidth(wide, origin, circle), 0.75 * circle.radius_px);
  cv::Mat disc = blank();
  cv::circle(disc, {100, 100}, 20, cv::Scalar(255), cv::FILLED);
  EXPECT_EQ(rimCrossingHalfWidth(disc, origin, circle), 0.0);

  const auto boll = discBoll(thin, origin, circle, 0.9, 100.0, kWholeWhiteShare);
  ASSERT_TRUE(boll);
  EXPECT_FALSE(boll->partial);
  EXPECT_EQ(boll->centre, circle.centre);
  EXPECT_EQ(boll->radius_px, circle.radius_px);
  EXPECT_NEAR(boll->confidence, 0.9, 0.1);
  EXPECT_NEAR(boll->centroid.x, 100.0, 1.0);

  cv::Mat half = blank();  // the left half of the disc: a boll partly hidden
  cv::circle(half, {100, 100}, 20, cv::Scalar(255), cv::FILLED);
  half(cv::Rect(100, 0, 200, 200)).setTo(0);
  const auto hidden = discBoll(half, origin, circle, 1.0, 100.0, 0.35);
  ASSERT_TRUE(hidden);
  EXPECT_TRUE(hidden->partial);
  EXPECT_NEAR(hidden->confidence, 0.5, 0.05);
  EXPECT_FALSE(discBoll(half, origin, circle, 1.0, 100.0, kWholeWhiteShare));

  const cv::Mat rest = restOffDisc(thin, origin, circle, 3);
  EXPECT_EQ(cv::countNonZero(rest(cv::Rect(79, 79, 42, 42))), 0);     // the disc and a pixel beyond it are gone
  EXPECT_GT(cv::countNonZero(rest(cv::Rect(130, 90, 50, 20))), 250);  // the bar stays
}
