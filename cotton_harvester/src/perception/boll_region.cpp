#include "cotton_harvester/perception/boll_region.h"

#include <algorithm>
#include <climits>
#include <cmath>
#include <limits>

#include <opencv2/imgproc.hpp>

namespace cotton_harvester {
namespace perception {

BollRegion cutBollRegion(const std::vector<cv::Point>& contour, const cv::Mat& bgr, const cv::Mat& mask,
                         double radius_min_px) {
  BollRegion region;
  region.box = cv::boundingRect(contour);
  const cv::Scalar mean_bgr = cv::mean(bgr(region.box), mask(region.box));
  region.brightness = std::max({mean_bgr[0], mean_bgr[1], mean_bgr[2]}) / 255.0;

  const int close_px = std::max(3, 2 * static_cast<int>(0.35 * radius_min_px) + 1);
  region.pad = close_px + 1;
  region.origin = cv::Point(region.box.x - region.pad, region.box.y - region.pad);
  region.pixels = cv::Mat::zeros(region.box.height + 2 * region.pad, region.box.width + 2 * region.pad, CV_8U);
  const std::vector<std::vector<cv::Point>> one{contour};
  cv::drawContours(region.pixels, one, 0, cv::Scalar(255), cv::FILLED, cv::LINE_8, cv::noArray(), INT_MAX,
                   -region.origin);
  cv::Mat closed;
  cv::morphologyEx(region.pixels, closed, cv::MORPH_CLOSE,
                   cv::getStructuringElement(cv::MORPH_ELLIPSE, {close_px, close_px}));
  cv::distanceTransform(closed, region.dist, cv::DIST_L2, cv::DIST_MASK_5);
  return region;
}

float neckBetween(const cv::Mat& dist, const cv::Point2f& a, const cv::Point2f& b) {
  const int samples = std::max(2, static_cast<int>(std::ceil(cv::norm(b - a))));
  float neck = std::numeric_limits<float>::infinity();
  for (int i = 0; i <= samples; ++i) {
    const cv::Point2f p = a + (b - a) * (static_cast<float>(i) / samples);
    neck = std::min(neck, dist.at<float>(cvRound(p.y), cvRound(p.x)));
  }
  return neck;
}

std::vector<BollPeak> findBollPeaks(const cv::Mat& dist, double min_radius, double neck_ratio, int window) {
  cv::Mat dilated;
  cv::dilate(dist, dilated, cv::getStructuringElement(cv::MORPH_RECT, {window, window}));
  std::vector<BollPeak> candidates;
  for (int v = 0; v < dist.rows; ++v) {
    const float* d = dist.ptr<float>(v);
    const float* m = dilated.ptr<float>(v);
    for (int u = 0; u < dist.cols; ++u)
      if (d[u] >= m[u] && d[u] >= min_radius) candidates.push_back({cv::Point2f(u, v), d[u]});
  }
  std::sort(candidates.begin(), candidates.end(),
            [](const BollPeak& a, const BollPeak& b) { return a.radius > b.radius; });
  constexpr size_t kMaxCandidates = 64;  // a plateau gives many equal maxima; the strongest few decide
  if (candidates.size() > kMaxCandidates) candidates.resize(kMaxCandidates);
  std::vector<BollPeak> kept;
  for (const BollPeak& candidate : candidates) {
    const bool separate = std::all_of(kept.begin(), kept.end(), [&](const BollPeak& other) {
      // Two touching bolls have their centres about the sum of their radii apart; lobes of one boll are closer.
      if (cv::norm(candidate.centre - other.centre) < 0.8 * (candidate.radius + other.radius)) return false;
      const float smaller = std::min(candidate.radius, other.radius);
      return neckBetween(dist, candidate.centre, other.centre) < neck_ratio * smaller;
    });
    if (separate) kept.push_back(candidate);
  }
  return kept;
}

}  // namespace perception
}  // namespace cotton_harvester
