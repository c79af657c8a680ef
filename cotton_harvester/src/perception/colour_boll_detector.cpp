#include "cotton_harvester/perception/colour_boll_detector.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

#include "cotton_harvester/perception/boll_peeling.h"
#include "cotton_harvester/perception/boll_shape.h"
#include "cotton_harvester/perception/touching_bolls.h"

namespace cotton_harvester {
namespace perception {

ColourBollDetector::ColourBollDetector(const ColourBollParams& params) : params_(params) {
  const std::string error = validate(params);
  if (!error.empty()) throw std::invalid_argument("colour boll detector parameters: " + error);
  setGeometry(CameraIntrinsics{}, BollGeometry{});
}

void ColourBollDetector::setGeometry(const CameraIntrinsics& intrinsics, const BollGeometry& geometry) {
  const std::string error = validate(intrinsics) + validate(geometry);
  if (!error.empty()) throw std::invalid_argument("colour boll detector geometry: " + error);
  const PixelRadiusRange radius = bollRadiusPx(geometry, 0.5 * (intrinsics.fx + intrinsics.fy));
  scale_.radius_min_px = radius.min_px;
  scale_.radius_max_px = radius.max_px;
  const double smallest_disc = CV_PI * radius.min_px * radius.min_px;
  const double largest_disc = CV_PI * radius.max_px * radius.max_px;
  scale_.min_area_px = std::max(4.0, params_.min_visible_fraction * smallest_disc);
  scale_.partial_min_area_px = std::max(scale_.min_area_px, params_.partial_min_fraction * smallest_disc);
  scale_.max_single_area_px = 1.3 * largest_disc;
  scale_.max_area_px = params_.max_cluster_bolls * largest_disc;
  // Odd sides, so that the structuring elements are centred and do not move the regions.
  const auto odd = [](double side) { return 2 * static_cast<int>(std::lround(0.5 * (side - 1.0))) + 1; };
  scale_.opening_px = odd(params_.opening_fraction * radius.min_px);
  scale_.closing_px = odd(params_.closing_fraction * radius.min_px);
}

BollCircleLimits ColourBollDetector::circleLimits() const {
  BollCircleLimits limits;
  limits.max_rms_fraction = params_.circle_max_rms_fraction;
  limits.min_arc_deg = params_.circle_min_arc_deg;
  limits.radius_min_px = scale_.radius_min_px;
  limits.radius_max_px = scale_.radius_max_px;
  return limits;
}

double ColourBollDetector::visibleShareMin() const {
  // Without partly hidden bolls, a boll must show what a whole one does.
  return params_.partial_min_visible > 0.0 ? params_.partial_min_visible : kWholeWhiteShare;
}

void ColourBollDetector::detectRegion(const std::vector<cv::Point>& contour, const cv::Mat& bgr, const cv::Mat& mask,
                                      int peels_left, std::vector<BollDetection>* bolls) const {
  const double area = cv::contourArea(contour);
  if (area < scale_.min_area_px || area > scale_.max_area_px) return;
  const BollRegion region = cutBollRegion(contour, bgr, mask, scale_.radius_min_px);
  const int window = 2 * std::max(1, static_cast<int>(0.5 * scale_.radius_min_px)) + 1;
  const std::vector<BollPeak> peaks =
      findBollPeaks(region.dist, std::max(1.5, 0.4 * scale_.radius_min_px), params_.split_neck_ratio, window);
  if (peaks.size() <= 1) {
    if (area > scale_.max_single_area_px) return;
    detectSingle(contour, area, region, peaks, bgr, mask, peels_left, bolls);
    return;
  }
  TouchingBollLimits limits;
  limits.min_area_px = scale_.min_area_px;
  limits.max_single_area_px = scale_.max_single_area_px;
  limits.max_aspect_ratio = params_.max_aspect_ratio;
  limits.visible_share_min = visibleShareMin();
  limits.circle = circleLimits();
  for (BollDetection& boll : splitTouchingBolls(region, peaks, limits)) bolls->push_back(std::move(boll));
}

void ColourBollDetector::detectSingle(const std::vector<cv::Point>& contour, double area, const BollRegion& region,
                                      const std::vector<BollPeak>& peaks, const cv::Mat& bgr, const cv::Mat& mask,
                                      int peels_left, std::vector<BollDetection>* bolls) const {
  const RegionShape shape = measureRegionShape(contour, area);
  const bool whole = wholeBollShape(shape, params_.min_circularity, params_.min_solidity, params_.max_aspect_ratio);
  // The boll's own silhouette: a circle through the outline's hull points (a leaf's cut runs inside the hull).
  const std::optional<BollCircle> circle = roundOutline(contour, circleLimits());
  const double disc_share = circle ? area / (CV_PI * circle->radius_px * circle->radius_px) : 0.0;
  const bool hidden_boll = !whole && circle && params_.partial_min_visible > 0.0 &&
                           disc_share >= params_.partial_min_visible && disc_share <= 1.15;
  // Not one round boll: a boll joined to something else by the closing or by touching it (another boll that the
  // distance transform does not tell apart, the sliver of one behind it, a glint, a label). The boll around the
  // distance transform's maximum is taken out on its own circle and the rest is looked at again.
  if (!peaks.empty() && !hidden_boll && !(whole && circle) && peels_left > 0) {
    const cv::Point2d peak(region.origin.x + peaks[0].centre.x, region.origin.y + peaks[0].centre.y);
    if (peelBoll(contour, region, peak, peaks[0].radius, bgr, mask, peels_left, bolls)) return;
  }
  bool partial = !whole && params_.partial_min_fraction > 0.0 && area >= scale_.partial_min_area_px;
  if (partial) {  // a part of one boll fits inside the largest boll's disc
    cv::Point2f centre;
    float radius = 0.0f;
    cv::minEnclosingCircle(contour, centre, radius);
    partial = radius <= scale_.radius_max_px;
  }
  if (whole && params_.whole_needs_arc && !circle) return;
  if (!whole && !partial && !hidden_boll) return;
  const cv::Moments m = cv::moments(contour);
  BollDetection boll;
  boll.box = region.box;
  boll.centroid = {m.m10 / m.m00, m.m01 / m.m00};
  if (whole) {
    boll.confidence = wholeBollConfidence(shape, region.brightness);
  } else if (hidden_boll) {
    boll.confidence = discCoverConfidence(disc_share, region.brightness);
  } else {
    boll.confidence = glimpseConfidence(shape, region.brightness);
  }
  boll.partial = !whole;
  boll.centre = circle ? circle->centre : boll.centroid;
  boll.radius_px = circle ? circle->radius_px : std::sqrt(area / CV_PI);
  boll.outline = contour;
  bolls->push_back(std::move(boll));
}

bool ColourBollDetector::peelBoll(const std::vector<cv::Point>& contour, const BollRegion& region,
                                  const cv::Point2d& peak, double peak_radius, const cv::Mat& bgr, const cv::Mat& mask,
                                  int peels_left, std::vector<BollDetection>* bolls) const {
  const std::optional<BollCircle> circle = lobeCircle(contour, peak, peak_radius, circleLimits());
  if (!circle) return false;
  // What else the region holds is joined to the boll by a neck, as touching bolls are (split_neck_ratio).
  if (rimCrossingHalfWidth(region.pixels, region.origin, *circle) > params_.split_neck_ratio * circle->radius_px)
    return false;
  std::optional<BollDetection> boll =
      discBoll(region.pixels, region.origin, *circle, region.brightness, scale_.min_area_px, visibleShareMin());
  if (!boll) return false;
  bolls->push_back(std::move(*boll));
  const cv::Mat rest = restOffDisc(region.pixels, region.origin, *circle, scale_.opening_px);
  std::vector<std::vector<cv::Point>> others;
  cv::findContours(rest, others, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE, region.origin);
  for (const std::vector<cv::Point>& other : others) detectRegion(other, bgr, mask, peels_left - 1, bolls);
  return true;
}

int ColourBollDetector::valueThreshold(const cv::Mat& bgr) const {
  // Median brightness (HSV value = largest channel) of the scene, from every fourth pixel of every fourth row.
  int histogram[256] = {0};
  int count = 0;
  for (int v = 0; v < bgr.rows; v += 4) {
    const cv::Vec3b* pixel = bgr.ptr<cv::Vec3b>(v);
    for (int u = 0; u < bgr.cols; u += 4, ++count) ++histogram[std::max({pixel[u][0], pixel[u][1], pixel[u][2]})];
  }
  int median = 0;
  for (int seen = 0; median < 255; ++median) {
    seen += histogram[median];
    if (2 * seen >= count) break;
  }
  const int relative = static_cast<int>(std::lround(params_.value_contrast * median));
  return std::clamp(relative, params_.value_floor, params_.value_min);
}

std::vector<BollDetection> ColourBollDetector::detect(const cv::Mat& bgr, const cv::Mat& exclude) {
  std::vector<BollDetection> bolls;
  if (bgr.empty() || bgr.type() != CV_8UC3) return bolls;

  cv::Mat mask = whitePixels(bgr, valueThreshold(bgr), params_.saturation_max);
  if (!exclude.empty() && exclude.size() == mask.size() && exclude.type() == CV_8U) mask.setTo(0, exclude);
  if (scale_.opening_px > 1) {
    const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_ELLIPSE, {scale_.opening_px, scale_.opening_px});
    cv::morphologyEx(mask, mask, cv::MORPH_OPEN, kernel);
  }
  // A twig or a leaf's edge across a boll cuts it in two: closing over a stem's width joins the pieces (bolls that
  // are joined this way are split again by their distance-transform maxima).
  if (scale_.closing_px > 1) {
    const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_ELLIPSE, {scale_.closing_px, scale_.closing_px});
    cv::morphologyEx(mask, mask, cv::MORPH_CLOSE, kernel);
    if (!exclude.empty() && exclude.size() == mask.size() && exclude.type() == CV_8U) mask.setTo(0, exclude);
  }

  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mask, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  for (const std::vector<cv::Point>& contour : contours)
    detectRegion(contour, bgr, mask, params_.max_cluster_bolls, &bolls);
  return bolls;
}

}  // namespace perception
}  // namespace cotton_harvester
