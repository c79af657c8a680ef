#include "cotton_harvester/perception/colour_boll_detector.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace cotton_harvester {
namespace perception {

std::string validate(const ColourBollParams& p) {
  std::ostringstream error;
  if (p.value_min < 0 || p.value_min > 255) error << "value_min must be in [0, 255] (got " << p.value_min << "); ";
  if (p.saturation_max < 0 || p.saturation_max > 255)
    error << "saturation_max must be in [0, 255] (got " << p.saturation_max << "); ";
  if (p.opening_px < 0) error << "opening_px must be >= 0 (got " << p.opening_px << "); ";
  if (p.min_area_px < 1 || p.max_area_px < p.min_area_px)
    error << "min_area_px/max_area_px must satisfy 1 <= min <= max (got " << p.min_area_px << ", " << p.max_area_px
          << "); ";
  if (!(p.min_circularity >= 0.0 && p.min_circularity <= 1.0))
    error << "min_circularity must be in [0, 1] (got " << p.min_circularity << "); ";
  if (!(p.min_solidity >= 0.0 && p.min_solidity <= 1.0))
    error << "min_solidity must be in [0, 1] (got " << p.min_solidity << "); ";
  if (!(p.max_aspect_ratio >= 1.0)) error << "max_aspect_ratio must be >= 1 (got " << p.max_aspect_ratio << "); ";
  return error.str();
}

ColourBollDetector::ColourBollDetector(const ColourBollParams& params) : params_(params) {
  const std::string error = validate(params);
  if (!error.empty()) throw std::invalid_argument("colour boll detector parameters: " + error);
}

std::vector<BollDetection> ColourBollDetector::detect(const cv::Mat& bgr, const cv::Mat& exclude) {
  std::vector<BollDetection> bolls;
  if (bgr.empty() || bgr.type() != CV_8UC3) return bolls;

  cv::Mat hsv, mask;
  cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);
  cv::inRange(hsv, cv::Scalar(0, 0, params_.value_min), cv::Scalar(180, params_.saturation_max, 255), mask);
  if (!exclude.empty() && exclude.size() == mask.size() && exclude.type() == CV_8U) mask.setTo(0, exclude);
  if (params_.opening_px > 1) {
    const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_ELLIPSE, {params_.opening_px, params_.opening_px});
    cv::morphologyEx(mask, mask, cv::MORPH_OPEN, kernel);
  }

  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mask, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
  std::vector<cv::Point> hull;
  for (const std::vector<cv::Point>& contour : contours) {
    const double area = cv::contourArea(contour);
    if (area < params_.min_area_px || area > params_.max_area_px) continue;
    const double perimeter = cv::arcLength(contour, true);
    const double circularity = perimeter > 0.0 ? std::min(1.0, 4.0 * CV_PI * area / (perimeter * perimeter)) : 0.0;
    if (circularity < params_.min_circularity) continue;
    cv::convexHull(contour, hull);
    const double hull_area = cv::contourArea(hull);
    const double solidity = hull_area > 0.0 ? area / hull_area : 0.0;
    if (solidity < params_.min_solidity) continue;
    const cv::Rect box = cv::boundingRect(contour);
    const double aspect = static_cast<double>(std::max(box.width, box.height)) / std::min(box.width, box.height);
    if (aspect > params_.max_aspect_ratio) continue;

    const cv::Moments m = cv::moments(contour);
    BollDetection boll;
    boll.box = box;
    boll.centroid = {m.m10 / m.m00, m.m01 / m.m00};
    const double brightness = cv::mean(hsv(box), mask(box))[2] / 255.0;
    boll.confidence = std::clamp(circularity * solidity * brightness, 0.0, 1.0);
    bolls.push_back(boll);
  }
  return bolls;
}

}  // namespace perception
}  // namespace cotton_harvester
