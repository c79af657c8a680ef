#include "cotton_harvester/perception/end_effector_detector.h"

#include <algorithm>
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

std::optional<EndEffectorColourSpace> parseEndEffectorColourSpace(const std::string& name) {
  if (name == "hsv") return EndEffectorColourSpace::kHsv;
  if (name == "rgb") return EndEffectorColourSpace::kRgb;
  return std::nullopt;
}

std::string toString(EndEffectorColourSpace space) { return space == EndEffectorColourSpace::kHsv ? "hsv" : "rgb"; }

std::string validate(const EndEffectorParams& params) {
  std::ostringstream error;
  if (params.hue_min < 0 || params.hue_min > 179 || params.hue_max < 0 || params.hue_max > 179)
    error << "hue_min/hue_max must be in [0, 179] (got " << params.hue_min << ", " << params.hue_max << "); ";
  if (params.saturation_min < 0 || params.saturation_min > 255)
    error << "saturation_min must be in [0, 255] (got " << params.saturation_min << "); ";
  if (params.value_min < 0 || params.value_min > 255)
    error << "value_min must be in [0, 255] (got " << params.value_min << "); ";
  if (params.glare_value_min < 0 || params.glare_value_min > 255 || params.glare_saturation_min < 0 ||
      params.glare_saturation_min > 255)
    error << "glare_value_min/glare_saturation_min must be in [0, 255]; ";
  if (!(params.reference_focal_px > 0.0)) error << "reference_focal_px must be > 0; ";
  if (!(params.arm_base_offset_m >= 0.0 && params.arm_base_offset_m < 10.0))
    error << "arm_base_offset_m must be in [0, 10) [m]; ";
  if (!(params.arm_depth_tolerance_m > 0.0 && params.arm_depth_tolerance_m < 1.0))
    error << "arm_depth_tolerance_m must be in (0, 1) [m]; ";
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

cv::Mat armMask(const cv::Size& size, const EndEffectorObservation& observation,
                const cv::Point3d& end_effector_position, const CameraIntrinsics& intrinsics, const cv::Mat& cloud,
                const EndEffectorParams& params) {
  cv::Mat band = cv::Mat::zeros(size, CV_8U);
  const double norm = std::hypot(params.arm_direction.x, params.arm_direction.y);
  if (!(norm > 0.0) || !(end_effector_position.z > 0.0)) return band;
  const cv::Point2d along = params.arm_direction / norm;
  const cv::Point2d across(-along.y, along.x);
  const double half = 0.5 * (std::abs(across.x) * observation.box.width + std::abs(across.y) * observation.box.height);
  const cv::Point2d centre(observation.box.x + 0.5 * observation.box.width,
                           observation.box.y + 0.5 * observation.box.height);
  // The base's distance from the end-effector along the arm, in pixels at the end-effector's depth.
  const double focal = 0.5 * (intrinsics.fx + intrinsics.fy);
  const double ee_along_m = end_effector_position.x * along.x + end_effector_position.y * along.y;
  const double length_px = std::max(0.0, (params.arm_base_offset_m - ee_along_m) * focal / end_effector_position.z);
  const cv::Point2d far = centre + along * length_px;
  const std::vector<cv::Point> corners = {cv::Point(centre + across * half), cv::Point(far + across * half),
                                          cv::Point(far - across * half), cv::Point(centre - across * half)};
  cv::fillConvexPoly(band, corners, cv::Scalar(255));
  if (cloud.empty() || cloud.type() != CV_32FC3 || cloud.size() != size) return band;
  const cv::Rect bounds = cv::boundingRect(corners) & cv::Rect(cv::Point(0, 0), size);
  const float low = static_cast<float>(end_effector_position.z - params.arm_depth_tolerance_m);
  const float high = static_cast<float>(end_effector_position.z + params.arm_depth_tolerance_m);
  for (int v = bounds.y; v < bounds.y + bounds.height; ++v) {
    uint8_t* inside = band.ptr<uint8_t>(v);
    const cv::Vec3f* point = cloud.ptr<cv::Vec3f>(v);
    for (int u = bounds.x; u < bounds.x + bounds.width; ++u) {
      const float z = point[u][2];
      if (inside[u] && std::isfinite(z) && (z < low || z > high)) inside[u] = 0;
    }
  }
  return band;
}

EndEffectorDetector::EndEffectorDetector(const EndEffectorParams& params)
    : params_(params), min_area_px_(params.min_area_px) {
  const std::string error = validate(params);
  if (!error.empty()) throw std::invalid_argument("end-effector parameters: " + error);
}

void EndEffectorDetector::setFocalLength(double focal_px) {
  if (!(focal_px > 0.0) || !std::isfinite(focal_px))
    throw std::invalid_argument("end-effector detector: focal length must be > 0");
  const double scale = focal_px / params_.reference_focal_px;
  min_area_px_ = std::max(4.0, params_.min_area_px * scale * scale);
}

cv::Mat EndEffectorDetector::colourMask(const cv::Mat& bgr) const {
  cv::Mat mask;
  if (params_.colour_space == EndEffectorColourSpace::kRgb) {
    cv::inRange(bgr, cv::Scalar(params_.b_min, params_.g_min, params_.r_min),
                cv::Scalar(params_.b_max, params_.g_max, params_.r_max), mask);
  } else {
    cv::Mat hsv;
    cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);
    const auto window = [&](int saturation_min, int value_min) {
      cv::Mat out;
      if (params_.hue_min <= params_.hue_max) {
        cv::inRange(hsv, cv::Scalar(params_.hue_min, saturation_min, value_min), cv::Scalar(params_.hue_max, 255, 255),
                    out);
      } else {  // the window wraps through red
        cv::Mat upper;
        cv::inRange(hsv, cv::Scalar(params_.hue_min, saturation_min, value_min), cv::Scalar(179, 255, 255), upper);
        cv::inRange(hsv, cv::Scalar(0, saturation_min, value_min), cv::Scalar(params_.hue_max, 255, 255), out);
        out |= upper;
      }
      return out;
    };
    mask = window(params_.saturation_min, params_.value_min);
    if (params_.glare_saturation_min < params_.saturation_min)
      mask |= window(params_.glare_saturation_min, std::max(params_.value_min, params_.glare_value_min));
  }
  return mask;
}

namespace {

/// Index of the largest contour of at least min_area [px^2], or -1.
int largestContour(const std::vector<std::vector<cv::Point>>& contours, double min_area, double* area_out) {
  int best = -1;
  double best_area = 0.0;
  for (size_t i = 0; i < contours.size(); ++i) {
    const double area = cv::contourArea(contours[i]);
    if (area >= min_area && area > best_area) {
      best = static_cast<int>(i);
      best_area = area;
    }
  }
  *area_out = best_area;
  return best;
}

}  // namespace

std::optional<EndEffectorObservation> EndEffectorDetector::detect(const cv::Mat& bgr, cv::Mat* mask_out) const {
  if (mask_out) mask_out->release();
  if (bgr.empty() || bgr.type() != CV_8UC3) return std::nullopt;

  // Coarse search at half resolution when the end-effector is large enough to survive it (a quarter of the
  // pixels to convert), then the exact segmentation at full resolution around what was found.
  const int scale = min_area_px_ >= 64.0 && bgr.cols >= 320 && bgr.rows >= 180 ? 2 : 1;
  cv::Rect roi(0, 0, bgr.cols, bgr.rows);
  std::vector<std::vector<cv::Point>> contours;
  double best_area = 0.0;
  if (scale > 1) {
    cv::Mat small;
    cv::resize(bgr, small, cv::Size(bgr.cols / scale, bgr.rows / scale), 0, 0, cv::INTER_AREA);
    cv::Mat coarse = colourMask(small);
    cv::findContours(coarse, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
    const int coarse_best = largestContour(contours, 0.5 * min_area_px_ / (scale * scale), &best_area);
    if (coarse_best < 0) return std::nullopt;
    const cv::Rect box = cv::boundingRect(contours[coarse_best]);
    const int margin = 2 * scale + params_.opening_px;
    roi = cv::Rect(box.x * scale - margin, box.y * scale - margin, box.width * scale + 2 * margin,
                   box.height * scale + 2 * margin) &
          roi;
    contours.clear();
  }

  contours = regions(bgr, roi);
  const int best = largestContour(contours, min_area_px_, &best_area);
  if (best < 0) return std::nullopt;
  const EndEffectorObservation observation = observationOf(contours[best], best_area);
  if (mask_out) {
    *mask_out = cv::Mat::zeros(bgr.size(), CV_8U);
    cv::drawContours(*mask_out, contours, best, cv::Scalar(255), cv::FILLED);
  }
  return observation;
}

std::vector<std::vector<cv::Point>> EndEffectorDetector::regions(const cv::Mat& bgr, const cv::Rect& roi) const {
  cv::Mat mask = colourMask(bgr(roi));
  if (params_.opening_px > 1) {
    const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_RECT, {params_.opening_px, params_.opening_px});
    cv::morphologyEx(mask, mask, cv::MORPH_OPEN, kernel);
  }
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mask, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE, roi.tl());
  return contours;
}

EndEffectorObservation EndEffectorDetector::observationOf(const std::vector<cv::Point>& contour, double area_px) const {
  EndEffectorObservation observation;
  observation.area_px = area_px;
  observation.box = cv::boundingRect(contour);
  if (params_.point == EndEffectorPoint::kCentroid) {
    const cv::Moments m = cv::moments(contour);
    observation.pixel = {m.m10 / m.m00, m.m01 / m.m00};
    return observation;
  }
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
  return observation;
}

std::vector<EndEffectorObservation> EndEffectorDetector::candidates(const cv::Mat& bgr, const cv::Rect& roi,
                                                                    std::vector<cv::Mat>* masks_out) const {
  if (masks_out) masks_out->clear();
  std::vector<EndEffectorObservation> found;
  if (bgr.empty() || bgr.type() != CV_8UC3) return found;
  const cv::Rect clipped = roi & cv::Rect(0, 0, bgr.cols, bgr.rows);
  if (clipped.area() == 0) return found;
  const std::vector<std::vector<cv::Point>> contours = regions(bgr, clipped);
  std::vector<std::pair<double, size_t>> by_area;
  for (size_t i = 0; i < contours.size(); ++i) {
    const double area = cv::contourArea(contours[i]);
    if (area >= min_area_px_) by_area.emplace_back(area, i);
  }
  std::sort(by_area.begin(), by_area.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  for (const auto& [area, i] : by_area) {
    found.push_back(observationOf(contours[i], area));
    if (masks_out) {
      masks_out->push_back(cv::Mat::zeros(bgr.size(), CV_8U));
      cv::drawContours(masks_out->back(), contours, static_cast<int>(i), cv::Scalar(255), cv::FILLED);
    }
  }
  return found;
}

}  // namespace perception
}  // namespace cotton_harvester
