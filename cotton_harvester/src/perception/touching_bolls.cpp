#include "cotton_harvester/perception/touching_bolls.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>

#include <opencv2/imgproc.hpp>

#include "cotton_harvester/perception/boll_shape.h"

namespace cotton_harvester {
namespace perception {
namespace {

/// The boll of part `index` (its pixels: owner == index + 1) around its peak, or std::nullopt outside the limits.
std::optional<BollDetection> partBoll(const BollRegion& region, const cv::Mat& owner, std::size_t index,
                                      const BollPart& part, const BollPeak& peak, const TouchingBollLimits& limits) {
  if (part.count < limits.min_area_px || part.count > limits.max_single_area_px) return std::nullopt;
  const int width = part.u_max - part.u_min + 1, height = part.v_max - part.v_min + 1;
  if (static_cast<double>(std::max(width, height)) / std::min(width, height) > limits.max_aspect_ratio)
    return std::nullopt;
  const cv::Point& origin = region.origin;
  BollDetection boll;
  boll.box = cv::Rect2d(origin.x + part.u_min, origin.y + part.v_min, width, height);
  boll.centroid = {origin.x + part.sum_u / part.count, origin.y + part.sum_v / part.count};
  const double fill = part.count / (CV_PI * peak.radius * peak.radius);
  boll.confidence = discCoverConfidence(std::min(1.0, fill), region.brightness);
  std::vector<std::vector<cv::Point>> outlines;
  cv::findContours(owner == static_cast<int>(index + 1), outlines, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE, origin);
  const auto largest = std::max_element(outlines.begin(), outlines.end(),
                                        [](const auto& a, const auto& b) { return a.size() < b.size(); });
  boll.centre = {origin.x + peak.centre.x, origin.y + peak.centre.y};
  boll.radius_px = peak.radius + 0.5;
  if (largest != outlines.end()) {
    boll.outline = std::move(*largest);
    const std::optional<BollCircle> circle = roundOutline(boll.outline, limits.circle);
    if (circle && holdsDisc(*circle, boll.centre, peak.radius) &&
        part.count >= limits.visible_share_min * CV_PI * circle->radius_px * circle->radius_px) {
      boll.centre = circle->centre;
      boll.radius_px = circle->radius_px;
    }
  }
  return boll;
}

}  // namespace

std::vector<BollPart> assignToPeaks(const BollRegion& region, const std::vector<BollPeak>& peaks, cv::Mat* owner) {
  std::vector<BollPart> parts(peaks.size());
  *owner = cv::Mat::zeros(region.pixels.size(), CV_8U);
  const int pad = region.pad;
  for (int v = pad; v < pad + region.box.height; ++v) {
    const uint8_t* inside = region.pixels.ptr<uint8_t>(v);
    uint8_t* owned = owner->ptr<uint8_t>(v);
    for (int u = pad; u < pad + region.box.width; ++u) {
      if (!inside[u]) continue;
      size_t best = 0;
      double best_cost = std::numeric_limits<double>::infinity();
      for (size_t i = 0; i < peaks.size(); ++i) {
        const double cost = std::hypot(u - peaks[i].centre.x, v - peaks[i].centre.y) - peaks[i].radius;
        if (cost < best_cost) {
          best_cost = cost;
          best = i;
        }
      }
      owned[u] = static_cast<uint8_t>(best + 1);
      BollPart& part = parts[best];
      part.count += 1.0;
      part.sum_u += u;
      part.sum_v += v;
      part.u_min = std::min(part.u_min, u);
      part.u_max = std::max(part.u_max, u);
      part.v_min = std::min(part.v_min, v);
      part.v_max = std::max(part.v_max, v);
    }
  }
  return parts;
}

std::vector<BollDetection> splitTouchingBolls(const BollRegion& region, const std::vector<BollPeak>& peaks,
                                              const TouchingBollLimits& limits) {
  cv::Mat owner;
  const std::vector<BollPart> parts = assignToPeaks(region, peaks, &owner);
  std::vector<BollDetection> bolls;
  for (std::size_t i = 0; i < parts.size(); ++i)
    if (auto boll = partBoll(region, owner, i, parts[i], peaks[i], limits)) bolls.push_back(std::move(*boll));
  return bolls;
}

}  // namespace perception
}  // namespace cotton_harvester
