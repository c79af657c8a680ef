#include "cotton_harvester/perception/perception_pipeline.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <opencv2/imgproc.hpp>

namespace cotton_harvester {
namespace perception {

std::optional<NearestBy> parseNearestBy(const std::string& name) {
  if (name == "camera") return NearestBy::kCamera;
  if (name == "end_effector") return NearestBy::kEndEffector;
  return std::nullopt;
}

std::string toString(NearestBy nearest_by) { return nearest_by == NearestBy::kCamera ? "camera" : "end_effector"; }

std::string toString(FrameStatus status) {
  switch (status) {
    case FrameStatus::kOk:
      return "ok";
    case FrameStatus::kEmptyImage:
      return "empty image";
    case FrameStatus::kBadImage:
      return "image is not 8-bit 3-channel";
    case FrameStatus::kSizeMismatch:
      return "image size differs from the camera intrinsics";
    case FrameStatus::kNoDepth:
      return "no organised cloud of the image's size";
  }
  return "?";
}

std::string toString(BollDepthSource source) {
  switch (source) {
    case BollDepthSource::kSurface:
      return "surface";
    case BollDepthSource::kWindow:
      return "window";
    case BollDepthSource::kImageSize:
      return "image_size";
  }
  return "?";
}

cv::Point3d centreBehindSurface(const cv::Point3d& surface, double radius_m) {
  const double norm = std::sqrt(surface.dot(surface));
  if (!(norm > 0.0)) return surface;
  return surface * ((norm + radius_m) / norm);
}

std::optional<LocatedPoint> locateBoxDisc(const cv::Mat& cloud, const BollDetection& detection,
                                          const CameraIntrinsics& intrinsics, const LocatorParams& params) {
  const double radius_px = imageRadiusPx(detection);
  if (!(radius_px > 1.0)) return std::nullopt;
  const cv::Point2d centre(detection.box.x + 0.5 * detection.box.width, detection.box.y + 0.5 * detection.box.height);
  std::vector<cv::Point> outline;
  cv::ellipse2Poly(cv::Point(static_cast<int>(std::lround(centre.x)), static_cast<int>(std::lround(centre.y))),
                   cv::Size(static_cast<int>(0.8 * radius_px) + 1, static_cast<int>(0.8 * radius_px) + 1), 0, 0, 360,
                   10, outline);
  return locateBollSurface(cloud, outline, centre, radius_px, intrinsics, params);
}

double imageRadiusPx(const BollDetection& detection) {
  if (detection.radius_px > 0.0) return detection.radius_px;
  return 0.25 * (detection.box.width + detection.box.height);
}

std::optional<LocatedBoll> locateBySize(const BollDetection& detection, const CameraIntrinsics& k,
                                        const BollGeometry& g, double ground_depth_m, DepthModel model) {
  const double radius_px = imageRadiusPx(detection);
  const cv::Point2d& pixel = detection.radius_px > 0.0 ? detection.centre : detection.centroid;
  if (!(radius_px > 0.0) || !std::isfinite(pixel.x) || !std::isfinite(pixel.y)) return std::nullopt;
  // A sphere of radius R at centre range D subtends the half angle asin(R / D); its image radius is about f R / D.
  const double focal = 0.5 * (k.fx + k.fy);
  const double ground = std::isfinite(ground_depth_m) ? ground_depth_m : g.camera_height_m;
  const double unit_z =
      1.0 / std::sqrt(1.0 + std::pow((pixel.x - k.cx) / k.fx, 2) + std::pow((pixel.y - k.cy) / k.fy, 2));
  const double z_centre = std::clamp(focal * g.boll_radius_typical_m / radius_px * unit_z,
                                     std::max(0.05, ground - g.boll_height_max_m), ground - g.boll_height_min_m);
  LocatedBoll boll;
  boll.detection = detection;
  boll.radius_m = g.boll_radius_typical_m;
  boll.centre = backProject(k, pixel, z_centre / unit_z, DepthModel::kRay);
  boll.range_m = z_centre / unit_z - boll.radius_m;
  boll.position = backProject(k, pixel, boll.range_m, model);
  boll.depth_source = BollDepthSource::kImageSize;
  return boll;
}

std::string validate(const PerceptionParams& params) {
  std::string error;
  const auto add = [&error](const std::string& prefix, const std::string& message) {
    if (!message.empty()) error += prefix + message;
  };
  add("camera: ", validate(params.intrinsics));
  add("end_effector: ", validate(params.end_effector));
  add("depth: ", validate(params.locator));
  add("reach: ", validate(params.reach));
  add("geometry: ", validate(params.geometry));
  if (!(params.boll_min_dome_fraction >= 0.0 && params.boll_min_dome_fraction <= 1.0))
    error += "boll_min_dome_fraction must be in [0, 1] (got " + std::to_string(params.boll_min_dome_fraction) + "); ";
  if (!(params.boll_top_fraction >= 0.0 && params.boll_top_fraction <= 1.0))
    error += "boll_top_fraction must be in [0, 1] (got " + std::to_string(params.boll_top_fraction) + "); ";
  if (!(params.boll_dome_sigmas >= 0.0 && params.boll_dome_sigmas <= 10.0))
    error += "boll_dome_sigmas must be in [0, 10] (got " + std::to_string(params.boll_dome_sigmas) + "); ";
  return error;
}

PerceptionPipeline::PerceptionPipeline(const PerceptionParams& params, std::unique_ptr<BollDetector> detector)
    : params_(params), end_effector_detector_(params.end_effector), detector_(std::move(detector)) {
  const std::string error = validate(params);
  if (!error.empty()) throw std::invalid_argument("perception parameters: " + error);
  if (!detector_) throw std::invalid_argument("perception pipeline needs a boll detector");
  applyGeometry();
}

void PerceptionPipeline::applyGeometry() {
  detector_->setGeometry(params_.intrinsics, params_.geometry);
  end_effector_detector_.setFocalLength(0.5 * (params_.intrinsics.fx + params_.intrinsics.fy));
}

void PerceptionPipeline::setIntrinsics(const CameraIntrinsics& intrinsics) {
  const std::string error = validate(intrinsics);
  if (!error.empty()) throw std::invalid_argument("camera intrinsics: " + error);
  params_.intrinsics = intrinsics;
  applyGeometry();
}

namespace {

/// Depth of the ground below the camera [m]: the 90th percentile of the cloud's depths on a sparse grid (the ground
/// is the farthest large surface). NaN when the cloud holds too few points.
double groundDepth(const cv::Mat& cloud) {
  std::vector<float> depths;
  depths.reserve(static_cast<size_t>(cloud.rows / 8 + 1) * (cloud.cols / 8 + 1));
  for (int v = 0; v < cloud.rows; v += 8) {
    const cv::Vec3f* point = cloud.ptr<cv::Vec3f>(v);
    for (int u = 0; u < cloud.cols; u += 8)
      if (std::isfinite(point[u][2]) && point[u][2] > 0.0f) depths.push_back(point[u][2]);
  }
  if (depths.size() < 50) return std::numeric_limits<double>::quiet_NaN();
  const auto at = depths.begin() + static_cast<std::ptrdiff_t>(0.9 * (depths.size() - 1));
  std::nth_element(depths.begin(), at, depths.end());
  return *at;
}

}  // namespace

bool PerceptionPipeline::plausible(const BollDetection& detection, const LocatedPoint& located,
                                   double ground_depth_m) const {
  const BollGeometry& g = params_.geometry;
  const cv::Point3d& position = located.position;
  // Nothing lower than half the lowest boll's height (stones, pale soil): above the measured ground when the cloud
  // shows it (terrain and the camera's height vary), else above the nominal one.
  const double ground = std::isfinite(ground_depth_m) ? ground_depth_m : g.camera_height_m;
  if (position.z > ground - 0.5 * g.boll_height_min_m) return false;
  // The visible extent at the measured depth must fit a boll: at least part of the smallest, at most the largest.
  const double focal = 0.5 * (params_.intrinsics.fx + params_.intrinsics.fy);
  const double extent_m = 0.5 * std::max(detection.box.width, detection.box.height) * position.z / focal;
  if (!(extent_m >= 0.4 * g.boll_radius_min_m && extent_m <= 1.5 * g.boll_radius_max_m)) return false;
  // A detector that estimates the boll's disc: it must be a boll's at the measured depth (the white part of a boll
  // ends a little inside its silhouette: 0.75 of the smallest).
  if (!(detection.radius_px > 0.0)) return true;
  const double radius_m = detection.radius_px * position.z / focal;
  if (!(radius_m >= 0.75 * g.boll_radius_min_m && radius_m <= 1.2 * g.boll_radius_max_m)) return false;
  // Its visible surface must bulge towards the camera as a boll's does; a flat white thing does not.
  return !(
      params_.boll_min_dome_fraction > 0.0 && std::isfinite(located.dome_m) && std::isfinite(located.dome_sigma_m) &&
      located.dome_m + params_.boll_dome_sigmas * located.dome_sigma_m < params_.boll_min_dome_fraction * radius_m);
}

std::string validate(const EndEffectorPrior& prior) {
  const cv::Point3d& p = prior.position;
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || !(p.z > 0.0))
    return "position must be finite with z > 0";
  if (!(prior.radius_m > 0.0) || !std::isfinite(prior.radius_m)) return "radius_m must be > 0";
  if (!(prior.housing_half_m > 0.0) || !std::isfinite(prior.housing_half_m)) return "housing_half_m must be > 0";
  return "";
}

void PerceptionPipeline::findEndEffectorNear(const cv::Mat& bgr, const cv::Mat& cloud, const EndEffectorPrior& prior,
                                             FrameResult* result) const {
  const CameraIntrinsics& k = params_.intrinsics;
  // The image box the housing can cover: its top face grown by the prior's radius, at the nearest depth it may have.
  const double reach = prior.housing_half_m + prior.radius_m;
  const double z_near = std::max(0.05, prior.position.z - prior.radius_m);
  const auto u = [&](double x) { return k.cx + k.fx * x / z_near; };
  const auto v = [&](double y) { return k.cy + k.fy * y / z_near; };
  const cv::Point top_left(static_cast<int>(std::floor(u(prior.position.x - reach))),
                           static_cast<int>(std::floor(v(prior.position.y - reach))));
  const cv::Point bottom_right(static_cast<int>(std::ceil(u(prior.position.x + reach))) + 1,
                               static_cast<int>(std::ceil(v(prior.position.y + reach))) + 1);
  std::vector<cv::Mat> masks;
  const std::vector<EndEffectorObservation> found =
      end_effector_detector_.candidates(bgr, cv::Rect(top_left, bottom_right), &masks);
  result->end_effector_candidates = static_cast<int>(found.size());
  const double focal = 0.5 * (k.fx + k.fy);
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < found.size(); ++i) {
    const std::optional<LocatedPoint> located = locateRegion(cloud, masks[i], found[i].pixel, k, params_.locator);
    bool accepted = false;
    if (located) {
      const cv::Point3d d = located->position - prior.position;
      const double distance = std::sqrt(d.dot(d));
      // A leaf may hide part of the housing, nothing makes it look larger: at most twice its top face's area.
      const double side_px = 2.0 * prior.housing_half_m * focal / located->position.z;
      accepted = distance <= prior.radius_m && found[i].area_px <= 2.0 * side_px * side_px;
      if (accepted && distance < best) {
        best = distance;
        result->end_effector_image = found[i];
        result->end_effector = located;
        result->end_effector_mask = masks[i];
      }
    }
    if (!accepted) ++result->end_effector_candidates_refused;
  }
}

FrameResult PerceptionPipeline::process(const cv::Mat& bgr, const cv::Mat& cloud) {
  return process(bgr, cloud, std::nullopt);
}

int nearestReachable(const std::vector<LocatedBoll>& bolls, const std::optional<LocatedPoint>& end_effector,
                     NearestBy nearest_by) {
  int nearest = -1;
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < bolls.size(); ++i) {
    const LocatedBoll& boll = bolls[i];
    if (!boll.reachable) continue;
    double distance = boll.range_m;
    if (nearest_by == NearestBy::kEndEffector && end_effector) {
      const cv::Point3d d = boll.position - end_effector->position;
      distance = std::sqrt(d.dot(d));
    }
    if (distance < best) {
      best = distance;
      nearest = static_cast<int>(i);
    }
  }
  return nearest;
}

namespace {

/// The housing's top face where the prior puts it, projected into the image: its centre pixel and its box.
EndEffectorObservation projectedHousing(const EndEffectorPrior& prior, const CameraIntrinsics& k) {
  const cv::Point3d& p = prior.position;
  const double e = prior.housing_half_m;
  EndEffectorObservation projected;
  projected.pixel = {k.cx + k.fx * p.x / p.z, k.cy + k.fy * p.y / p.z};
  projected.box = cv::Rect(
      cv::Point(static_cast<int>(k.cx + k.fx * (p.x - e) / p.z), static_cast<int>(k.cy + k.fy * (p.y - e) / p.z)),
      cv::Point(static_cast<int>(k.cx + k.fx * (p.x + e) / p.z) + 1,
                static_cast<int>(k.cy + k.fy * (p.y + e) / p.z) + 1));
  return projected;
}

}  // namespace

FrameStatus PerceptionPipeline::checkImage(const cv::Mat& bgr) const {
  if (bgr.empty()) return FrameStatus::kEmptyImage;
  if (bgr.type() != CV_8UC3) return FrameStatus::kBadImage;
  if (bgr.cols != params_.intrinsics.width || bgr.rows != params_.intrinsics.height) return FrameStatus::kSizeMismatch;
  return FrameStatus::kOk;
}

void PerceptionPipeline::findEndEffectorAndArm(const cv::Mat& bgr, const cv::Mat& cloud, bool has_depth,
                                               const std::optional<EndEffectorPrior>& prior,
                                               FrameResult* result) const {
  const bool use_prior = prior && has_depth && validate(*prior).empty();
  if (use_prior)
    findEndEffectorNear(bgr, cloud, *prior, result);
  else
    result->end_effector_image = end_effector_detector_.detect(bgr, &result->end_effector_mask);
  if (result->end_effector_image) {
    if (has_depth && !use_prior)
      result->end_effector = locateRegion(cloud, result->end_effector_mask, result->end_effector_image->pixel,
                                          params_.intrinsics, params_.locator);
    result->boll_exclusion = result->end_effector
                                 ? armMask(bgr.size(), *result->end_effector_image, result->end_effector->position,
                                           params_.intrinsics, cloud, params_.end_effector)
                                 : armBandMask(bgr.size(), *result->end_effector_image, params_.end_effector);
    result->boll_exclusion |= result->end_effector_mask;
  } else if (use_prior) {
    // The housing is hidden (a leaf) or not where the arm is: the arm is still masked where its sensing puts it.
    result->boll_exclusion = armMask(bgr.size(), projectedHousing(*prior, params_.intrinsics), prior->position,
                                     params_.intrinsics, cloud, params_.end_effector);
  }
}

void PerceptionPipeline::locateBolls(const std::vector<BollDetection>& detections, const cv::Mat& cloud,
                                     FrameResult* result) const {
  const double ground_depth_m = detections.empty() ? 0.0 : groundDepth(cloud);
  const double focal = 0.5 * (params_.intrinsics.fx + params_.intrinsics.fy);
  const BollGeometry& g = params_.geometry;
  for (const BollDetection& detection : detections) {
    // A detector that estimates the boll's disc: its depth from the visible surface, at its centre. Otherwise (or
    // without enough valid points under the outline) the window around the centroid.
    std::optional<LocatedPoint> located;
    BollDepthSource source = BollDepthSource::kSurface;
    if (params_.locator.boll_surface && detection.radius_px > 0.0 && !detection.outline.empty())
      located = locateBollSurface(cloud, detection.outline, detection.centre, detection.radius_px, params_.intrinsics,
                                  params_.locator);
    if (!located) {
      located = locate(cloud, detection.centroid, params_.intrinsics, params_.locator);
      source = BollDepthSource::kWindow;
    }
    // A box detector's boll whose centre has no depth (a passive stereo camera matches nothing on a uniform or
    // saturated lint face): the visible surface under the disc inscribed in its box.
    if (!located && params_.locator.boll_surface && !(detection.radius_px > 0.0)) {
      located = locateBoxDisc(cloud, detection, params_.intrinsics, params_.locator);
      source = BollDepthSource::kSurface;
    }
    if (!located) {
      std::optional<LocatedBoll> sized;
      if (params_.size_fallback)
        sized = locateBySize(detection, params_.intrinsics, g, ground_depth_m, params_.locator.depth_model);
      if (!sized) {
        ++result->bolls_without_depth;
        result->dropped.push_back({detection, true, cv::Point3d()});
        continue;
      }
      sized->reachable = isReachable(sized->position, params_.reach);
      result->bolls.push_back(*sized);
      ++result->bolls_size_fallback;
      continue;
    }
    if (params_.check_plausibility && !plausible(detection, *located, ground_depth_m)) {
      ++result->bolls_implausible;
      result->dropped.push_back({detection, false, located->position});
      continue;
    }
    LocatedBoll boll;
    boll.detection = detection;
    boll.position = located->position;
    boll.range_m = located->range_m;
    boll.reachable = isReachable(located->position, params_.reach);
    boll.dome_m = located->dome_m;
    boll.dome_sigma_m = located->dome_sigma_m;
    boll.depth_source = source;
    boll.valid_points = located->valid_points;
    // The boll's radius from its image radius at its range (a sphere's disc subtends asin(R / D), D = range + R).
    const double sin_a = std::min(0.5, imageRadiusPx(detection) / focal);
    boll.radius_m = std::clamp(located->range_m * sin_a / (1.0 - sin_a), g.boll_radius_min_m, g.boll_radius_max_m);
    boll.centre = centreBehindSurface(boll.position, params_.boll_top_fraction * boll.radius_m);
    result->bolls.push_back(boll);
  }
}

FrameResult PerceptionPipeline::process(const cv::Mat& bgr, const cv::Mat& cloud,
                                        const std::optional<EndEffectorPrior>& prior) {
  FrameResult result;
  result.status = checkImage(bgr);
  if (result.status != FrameStatus::kOk) return result;
  const bool has_depth = !cloud.empty() && cloud.type() == CV_32FC3 && cloud.size() == bgr.size();

  // Steps 1-3: end-effector, then bolls outside its region and the arm's.
  findEndEffectorAndArm(bgr, cloud, has_depth, prior, &result);
  const std::vector<BollDetection> detections = detector_->detect(bgr, result.boll_exclusion);
  result.bolls_detected = static_cast<int>(detections.size());
  if (!has_depth) {
    result.status = FrameStatus::kNoDepth;
    result.bolls_without_depth = result.bolls_detected;
    return result;
  }
  // Steps 4-5: depth of each centroid; step 7: its position; step 6: the closest reachable boll.
  locateBolls(detections, cloud, &result);
  result.nearest_reachable = nearestReachable(result.bolls, result.end_effector, params_.nearest_by);
  return result;
}

}  // namespace perception
}  // namespace cotton_harvester
