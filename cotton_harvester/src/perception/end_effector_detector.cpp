#include "cotton_harvester/perception/end_effector_detector.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <opencv2/imgproc.hpp>

namespace cotton_harvester {
namespace perception {
namespace {

void checkWindow(std::ostringstream& error, const char* name, int low, int high) {
  if (low < 0 || high > 255 || low > high)
    error << name << "_min/" << name << "_max must satisfy 0 <= min <= max <= 255 (got " << low << ", " << high
          << "); ";
}

}  // namespace

std::string validate(const EndEffectorParams& params) {
  std::ostringstream error;
  checkWindow(error, "r", params.r_min, params.r_max);
  checkWindow(error, "g", params.g_min, params.g_max);
  checkWindow(error, "b", params.b_min, params.b_max);
  if (params.min_area_px < 1) error << "min_area_px must be >= 1 (got " << params.min_area_px << "); ";
  if (params.opening_px < 0) error << "opening_px must be >= 0 (got " << params.opening_px << "); ";
  const double norm = std::hypot(params.tip_direction.x, params.tip_direction.y);
  if (params.point == EndEffectorPoint::kTip && !(norm > 0.0)) error << "tip_direction must be non-zero; ";
  if (!std::isfinite(params.arm_direction.x) || !std::isfinite(params.arm_direction.y))
    error << "arm_direction must be finite ((0, 0) disables the arm mask); ";
  return error.str();
}

cv::Mat armBandMask(const cv::Size& size, const EndEffectorObservation& observation, const EndEffectorParams& params) {
  cv::Mat band = cv::Mat::zeros(size, CV_8U);
  const double norm = std::hypot(params.arm_direction.x, params.arm_direction.y);
  if (!(norm > 0.0)) return band;
  const cv::Point2d along = params.arm_direction / norm;
  const cv::Point2d across(-along.y, along.x);
  // Half width: the bounding box's half extent across the arm.
  const double half = 0.5 * (std::abs(across.x) * observation.box.width + std::abs(across.y) * observation.box.height);
  const cv::Point2d centre(observation.box.x + 0.5 * observation.box.width,
                           observation.box.y + 0.5 * observation.box.height);
  const double length = std::hypot(size.width, size.height) + 1.0;
  const cv::Point2d far = centre + along * length;
  const std::vector<cv::Point> corners = {cv::Point(centre + across * half), cv::Point(far + across * half),
                                          cv::Point(far - across * half), cv::Point(centre - across * half)};
  cv::fillConvexPoly(band, corners, cv::Scalar(255));
  return band;
}

EndEffectorDetector::EndEffectorDetector(const EndEffectorParams& params) : params_(params) {
  const std::string error = validate(params);
  if (!error.empty()) throw std::invalid_argument("end-effector parameters: " + error);
}

std::optional<EndEffectorObservation> EndEffectorDetector::detect(const cv::Mat& bgr, cv::Mat* mask_out) const {
  if (mask_out) mask_out->release();
  if (bgr.empty() || bgr.type() != CV_8UC3) return std::nullopt;

  cv::Mat mask;
  cv::inRange(bgr, cv::Scalar(params_.b_min, params_.g_min, params_.r_min),
              cv::Scalar(params_.b_max, params_.g_max, params_.r_max), mask);
  if (params_.opening_px > 1) {
    const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_RECT, {params_.opening_px, params_.opening_px});
    cv::morphologyEx(mask, mask, cv::MORPH_OPEN, kernel);
  }

  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mask, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  int best = -1;
  double best_area = 0.0;
  for (size_t i = 0; i < contours.size(); ++i) {
    const double area = cv::contourArea(contours[i]);
    if (area >= params_.min_area_px && area > best_area) {
      best = static_cast<int>(i);
      best_area = area;
    }
  }
  if (best < 0) return std::nullopt;

  const std::vector<cv::Point>& contour = contours[best];
  EndEffectorObservation observation;
  observation.area_px = best_area;
  observation.box = cv::boundingRect(contour);
  if (params_.point == EndEffectorPoint::kCentroid) {
    const cv::Moments m = cv::moments(contour);
    observation.pixel = {m.m10 / m.m00, m.m01 / m.m00};
  } else {
    const double norm = std::hypot(params_.tip_direction.x, params_.tip_direction.y);
    const cv::Point2d direction = params_.tip_direction / norm;
    // The tip is the mean of the contour points within one pixel of the extreme projection, so that a flat
    // front edge gives its middle rather than a corner.
    double extreme = -std::numeric_limits<double>::infinity();
    for (const cv::Point& p : contour) extreme = std::max(extreme, direction.x * p.x + direction.y * p.y);
    cv::Point2d sum(0.0, 0.0);
    int count = 0;
    for (const cv::Point& p : contour) {
      if (direction.x * p.x + direction.y * p.y >= extreme - 1.0) {
        sum += cv::Point2d(p.x, p.y);
        ++count;
      }
    }
    observation.pixel = sum / count;
  }
  if (mask_out) {
    *mask_out = cv::Mat::zeros(bgr.size(), CV_8U);
    cv::drawContours(*mask_out, contours, best, cv::Scalar(255), cv::FILLED);
  }
  return observation;
}

}  // namespace perception
}  // namespace cotton_harvester
