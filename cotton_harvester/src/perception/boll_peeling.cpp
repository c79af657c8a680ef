#include "cotton_harvester/perception/boll_peeling.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "cotton_harvester/perception/boll_shape.h"
#include "cotton_harvester/perception/colour_boll_params.h"

namespace cotton_harvester {
namespace perception {
namespace {

/// A length in image pixels with 4 fractional bits, as cv::circle's shift takes it.
int fixed(double x) { return static_cast<int>(std::lround(16.0 * x)); }

/// The circle's centre in the region's pixels, with 4 fractional bits.
cv::Point localCentre16(const cv::Point& origin, const BollCircle& circle) {
  return cv::Point(fixed(circle.centre.x - origin.x), fixed(circle.centre.y - origin.y));
}

}  // namespace

double rimCrossingHalfWidth(const cv::Mat& region, const cv::Point& origin, const BollCircle& circle) {
  const double rim = circle.radius_px + 1.5;
  const int samples = static_cast<int>(std::ceil(2.0 * CV_PI * rim));
  std::vector<char> crossing(samples);
  for (int k = 0; k < samples; ++k) {
    const double angle = 2.0 * CV_PI * k / samples;
    const int u = static_cast<int>(std::lround(circle.centre.x - origin.x + rim * std::cos(angle)));
    const int v = static_cast<int>(std::lround(circle.centre.y - origin.y + rim * std::sin(angle)));
    crossing[k] = u >= 0 && v >= 0 && u < region.cols && v < region.rows && region.at<uint8_t>(v, u) != 0;
  }
  int longest = 0;
  for (int k = 0, run = 0; k < 2 * samples; ++k) {  // twice around: a run may wrap
    run = crossing[k % samples] ? run + 1 : 0;
    longest = std::max(longest, std::min(run, samples));
  }
  const double run_angle = 2.0 * CV_PI * longest / samples;
  return run_angle >= CV_PI ? rim : rim * std::sin(0.5 * run_angle);
}

std::optional<BollDetection> discBoll(const cv::Mat& region, const cv::Point& origin, const BollCircle& circle,
                                      double brightness, double min_area_px, double visible_share_min) {
  cv::Mat own = cv::Mat::zeros(region.size(), CV_8U);
  cv::circle(own, localCentre16(origin, circle), fixed(circle.radius_px + 0.5), cv::Scalar(255), cv::FILLED, cv::LINE_8,
             4);
  own &= region;
  const cv::Moments m = cv::moments(own, true);
  const double disc_area = CV_PI * circle.radius_px * circle.radius_px;
  const double share = m.m00 / disc_area;
  if (m.m00 < min_area_px || share < visible_share_min) return std::nullopt;
  std::vector<std::vector<cv::Point>> outlines;
  cv::findContours(own, outlines, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE, origin);
  const auto largest = std::max_element(outlines.begin(), outlines.end(),
                                        [](const auto& a, const auto& b) { return a.size() < b.size(); });
  if (largest == outlines.end()) return std::nullopt;
  BollDetection boll;
  boll.outline = std::move(*largest);
  boll.box = cv::boundingRect(boll.outline);
  boll.centroid = {origin.x + m.m10 / m.m00, origin.y + m.m01 / m.m00};
  boll.confidence = discCoverConfidence(std::min(1.0, share), brightness);
  boll.partial = share < kWholeWhiteShare;
  boll.centre = circle.centre;
  boll.radius_px = circle.radius_px;
  return boll;
}

cv::Mat restOffDisc(const cv::Mat& region, const cv::Point& origin, const BollCircle& circle, int opening_px) {
  cv::Mat rest = region.clone();
  cv::circle(rest, localCentre16(origin, circle), fixed(circle.radius_px + 1.5), cv::Scalar(0), cv::FILLED, cv::LINE_8,
             4);
  if (opening_px > 1)
    cv::morphologyEx(rest, rest, cv::MORPH_OPEN,
                     cv::getStructuringElement(cv::MORPH_ELLIPSE, {opening_px, opening_px}));
  return rest;
}

}  // namespace perception
}  // namespace cotton_harvester
