#include "cotton_harvester/perception/boll_locator.h"

#include <algorithm>
#include <climits>
#include <limits>
#include <cmath>
#include <sstream>
#include <vector>

#include <opencv2/imgproc.hpp>

namespace cotton_harvester {
namespace perception {

std::string validate(const LocatorParams& params) {
  std::ostringstream error;
  if (params.window_px < 1 || params.window_px % 2 == 0)
    error << "window_px must be an odd number >= 1 (got " << params.window_px << "); ";
  if (params.min_valid_points < 1) error << "min_valid_points must be >= 1 (got " << params.min_valid_points << "); ";
  if (params.min_valid_points > params.window_px * params.window_px)
    error << "min_valid_points must not exceed window_px^2 (got " << params.min_valid_points << "); ";
  return error.str();
}

namespace {

/// Range of a cloud point (eq. 6), or a negative number when the point is no measurement.
double pointRange(const cv::Vec3f& p) {
  if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) return -1.0;
  const double r = std::sqrt(double(p[0]) * p[0] + double(p[1]) * p[1] + double(p[2]) * p[2]);
  return r > 0.0 ? r : -1.0;
}

double median(std::vector<double>& values) {
  const size_t middle = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + middle, values.end());
  double m = values[middle];
  if (values.size() % 2 == 0) m = 0.5 * (m + *std::max_element(values.begin(), values.begin() + middle));
  return m;
}

/// The depth of a region facing the camera from the valid depths of `samples` pixels under its mask (see
/// locateRegion): their median while most pixels carry depth; when most do not (a uniform or saturated face that
/// the stereo matcher cannot match), the median of the nearest quarter, since what is left are the face's rim and
/// the sides below it, which lie deeper than the face.
double regionDepth(std::vector<double>& depths, int samples) {
  if (2 * depths.size() >= static_cast<size_t>(samples)) return median(depths);
  const size_t quarter = std::max<size_t>(1, depths.size() / 4);
  std::nth_element(depths.begin(), depths.begin() + quarter, depths.end());
  depths.resize(quarter);
  return median(depths);
}

/// A valid cloud point under a boll's outline: its pixel and its range [m].
struct SurfaceSample {
  cv::Vec3d ray;  ///< unit viewing ray of its pixel
  double range_m = 0.0;
};

cv::Vec3d unitRay(const cv::Point2d& pixel, const CameraIntrinsics& k) {
  const cv::Vec3d r((pixel.x - k.cx) / k.fx, (pixel.y - k.cy) / k.fy, 1.0);
  return r / cv::norm(r);
}

/// The point of a sphere nearest the lens: its pixel and range.
struct Apex {
  cv::Point2d pixel;
  double range_m = 0.0;
};

/// The sphere's range profile: a sphere of centre distance `distance` [m] and half angle asin(sin_a) whose centre
/// lies along the unit ray `axis`, seen along the unit ray `ray`. NaN off the sphere.
double sphereRange(const cv::Vec3d& ray, const cv::Vec3d& axis, double distance, double sin_a) {
  const double cos_t = std::min(1.0, axis.dot(ray));
  const double sin2_t = std::max(0.0, 1.0 - cos_t * cos_t);
  if (sin2_t > sin_a * sin_a) return std::numeric_limits<double>::quiet_NaN();
  return distance * (cos_t - std::sqrt(sin_a * sin_a - sin2_t));
}

/// Fits the apex pixel and the sphere's distance to the samples' ranges (Gauss-Newton on the sphere's range profile
/// with the half angle fixed; samples more than 3 robust sigmas off the fit are left out after the first pass). The
/// apex is the surface point on the ray through the sphere's centre wherever the boll's white part lies on it.
/// std::nullopt when the fit does not settle within half the disc's radius of `start`.
std::optional<Apex> fitApex(const std::vector<SurfaceSample>& samples, const cv::Point2d& start, double radius_px,
                            double distance, double sin_a, const CameraIntrinsics& k) {
  if (samples.size() < 12) return std::nullopt;
  cv::Point2d apex = start;
  std::vector<char> used(samples.size(), 1);
  constexpr double kStep = 0.25;  // [px], numerical derivative
  for (int iteration = 0; iteration < 5; ++iteration) {
    const cv::Vec3d axis = unitRay(apex, k), axis_u = unitRay(apex + cv::Point2d(kStep, 0.0), k),
                    axis_v = unitRay(apex + cv::Point2d(0.0, kStep), k);
    cv::Matx33d normal = cv::Matx33d::zeros();
    cv::Vec3d rhs(0.0, 0.0, 0.0);
    std::vector<double> residuals;
    residuals.reserve(samples.size());
    for (size_t i = 0; i < samples.size(); ++i) {
      const SurfaceSample& sample = samples[i];
      const double model = sphereRange(sample.ray, axis, distance, sin_a);
      const double du = sphereRange(sample.ray, axis_u, distance, sin_a);
      const double dv = sphereRange(sample.ray, axis_v, distance, sin_a);
      if (!std::isfinite(model) || !std::isfinite(du) || !std::isfinite(dv)) continue;
      const double error = sample.range_m - model;
      residuals.push_back(std::abs(error));
      if (!used[i]) continue;
      const cv::Vec3d j((du - model) / kStep, (dv - model) / kStep, model / distance);
      for (int r = 0; r < 3; ++r) {
        rhs[r] += j[r] * error;
        for (int c = 0; c < 3; ++c) normal(r, c) += j[r] * j[c];
      }
    }
    if (residuals.size() < 12) return std::nullopt;
    cv::Vec3d step;
    if (!cv::solve(normal, rhs, step, cv::DECOMP_CHOLESKY)) return std::nullopt;
    apex += cv::Point2d(step[0], step[1]);
    distance += step[2];
    if (!std::isfinite(apex.x) || !std::isfinite(apex.y) || !(distance > 0.0)) return std::nullopt;
    if (cv::norm(apex - start) > 0.5 * radius_px) return std::nullopt;
    // Outliers (a leaf's edge, the ground past the rim) against the first fit's robust spread.
    if (iteration == 0) {
      const double sigma = 1.4826 * median(residuals);
      const cv::Vec3d moved = unitRay(apex, k);
      for (size_t i = 0; i < samples.size(); ++i) {
        const double model = sphereRange(samples[i].ray, moved, distance, sin_a);
        used[i] = std::isfinite(model) && std::abs(samples[i].range_m - model) <= 3.0 * sigma + 1e-4;
      }
    }
  }
  return Apex{apex, distance * (1.0 - sin_a)};
}

/// A point of the visible surface for the dome fit: its pixel's offset from the disc's centre in disc radii (s, t)
/// and its depth [m].
struct DomeSample {
  double s = 0.0, t = 0.0, z = 0.0;
};

/// Least squares z = z0 + b s + c t + h (s^2 + t^2) over the used samples: h and its standard error, the residuals
/// of every sample in `residuals`. false when the fit is singular.
bool fitDomeOnce(const std::vector<DomeSample>& samples, const std::vector<char>& used, double* height, double* sigma,
                 std::vector<double>* residuals) {
  cv::Matx44d normal = cv::Matx44d::zeros();
  cv::Vec4d rhs(0.0, 0.0, 0.0, 0.0);
  int n = 0;
  for (size_t i = 0; i < samples.size(); ++i) {
    if (!used[i]) continue;
    const DomeSample& p = samples[i];
    const cv::Vec4d f(1.0, p.s, p.t, p.s * p.s + p.t * p.t);
    for (int r = 0; r < 4; ++r) {
      rhs[r] += f[r] * p.z;
      for (int c = r; c < 4; ++c) normal(r, c) += f[r] * f[c];
    }
    ++n;
  }
  if (n < 12) return false;
  for (int r = 1; r < 4; ++r)
    for (int c = 0; c < r; ++c) normal(r, c) = normal(c, r);
  cv::Matx44d inverse;
  if (cv::invert(normal, inverse, cv::DECOMP_CHOLESKY) == 0.0) return false;
  const cv::Vec4d x = inverse * rhs;
  double squares = 0.0;
  residuals->resize(samples.size());
  for (size_t i = 0; i < samples.size(); ++i) {
    const DomeSample& p = samples[i];
    const double r = p.z - (x[0] + x[1] * p.s + x[2] * p.t + x[3] * (p.s * p.s + p.t * p.t));
    (*residuals)[i] = r;
    if (used[i]) squares += r * r;
  }
  *height = x[3];
  *sigma = std::sqrt(squares / (n - 4) * std::max(0.0, inverse(3, 3)));
  return std::isfinite(*height) && std::isfinite(*sigma);
}

/// The dome of a boll's visible surface (see locateBollSurface): a fit over the samples within `reach` times their
/// median depth of it, then again without the samples more than 3 robust sigmas off it (a twig or a leaf's edge
/// inside the outline, the ground past the rim). The visible cap of a sphere of radius R spans less than R in depth,
/// from its apex to its rim, so its samples lie well within 1.5 R of their median depth; what lies farther is another
/// surface (a boll in front of it or behind it whose pixels the outline takes in, a leaf, the ground), which would
/// otherwise tilt the first fit so far that the second cannot recover.
bool fitDome(const std::vector<DomeSample>& samples, double reach, double* height, double* sigma) {
  if (samples.empty()) return false;
  std::vector<double> depths(samples.size());
  std::transform(samples.begin(), samples.end(), depths.begin(), [](const DomeSample& p) { return p.z; });
  const double middle = median(depths);
  std::vector<char> near(samples.size());
  for (size_t i = 0; i < samples.size(); ++i) near[i] = std::abs(samples[i].z - middle) <= reach * middle;
  std::vector<char> used = near;
  std::vector<double> residuals;
  if (!fitDomeOnce(samples, used, height, sigma, &residuals)) return false;
  std::vector<double> spread;
  spread.reserve(residuals.size());
  for (size_t i = 0; i < samples.size(); ++i)
    if (near[i]) spread.push_back(std::abs(residuals[i]));
  const double limit = 3.0 * 1.4826 * median(spread) + 1e-4;
  for (size_t i = 0; i < samples.size(); ++i) used[i] = near[i] && std::abs(residuals[i]) <= limit;
  return fitDomeOnce(samples, used, height, sigma, &residuals);
}

}  // namespace

std::optional<LocatedPoint> locate(const cv::Mat& cloud, const cv::Point2d& pixel, const CameraIntrinsics& intrinsics,
                                   const LocatorParams& params) {
  if (cloud.empty() || cloud.type() != CV_32FC3) return std::nullopt;
  if (!std::isfinite(pixel.x) || !std::isfinite(pixel.y)) return std::nullopt;
  const int u = static_cast<int>(std::lround(pixel.x));
  const int v = static_cast<int>(std::lround(pixel.y));
  if (u < 0 || v < 0 || u >= cloud.cols || v >= cloud.rows) return std::nullopt;

  const int half = params.window_px / 2;
  std::vector<double> ranges;
  ranges.reserve(static_cast<size_t>(params.window_px) * params.window_px);
  for (int row = std::max(0, v - half); row <= std::min(cloud.rows - 1, v + half); ++row) {
    const cv::Vec3f* points = cloud.ptr<cv::Vec3f>(row);
    for (int col = std::max(0, u - half); col <= std::min(cloud.cols - 1, u + half); ++col) {
      const double r = pointRange(points[col]);
      if (r > 0.0) ranges.push_back(r);
    }
  }
  if (static_cast<int>(ranges.size()) < params.min_valid_points) return std::nullopt;
  LocatedPoint located;
  located.valid_points = static_cast<int>(ranges.size());
  located.range_m = median(ranges);
  located.position = backProject(intrinsics, pixel, located.range_m, params.depth_model);
  return located;
}

std::optional<LocatedPoint> locateRegion(const cv::Mat& cloud, const cv::Mat& mask, const cv::Point2d& pixel,
                                         const CameraIntrinsics& intrinsics, const LocatorParams& params) {
  if (cloud.empty() || cloud.type() != CV_32FC3 || mask.size() != cloud.size() || mask.type() != CV_8U)
    return std::nullopt;
  if (!std::isfinite(pixel.x) || !std::isfinite(pixel.y)) return std::nullopt;
  const cv::Rect box = cv::boundingRect(mask);
  if (box.area() == 0) return std::nullopt;
  // At most about 4000 samples: a regular subsampling of large regions. Each point's depth along the optical
  // axis is used, so that a region facing the camera gets one depth wherever its points lie in the image.
  const int stride = std::max(1, static_cast<int>(std::sqrt(box.area() / 4000.0)));
  std::vector<double> depths;
  int samples = 0;
  for (int row = box.y; row < box.y + box.height; row += stride) {
    const uint8_t* inside = mask.ptr<uint8_t>(row);
    const cv::Vec3f* points = cloud.ptr<cv::Vec3f>(row);
    for (int col = box.x; col < box.x + box.width; col += stride) {
      if (!inside[col]) continue;
      ++samples;
      if (pointRange(points[col]) > 0.0 && points[col][2] > 0.0f) depths.push_back(points[col][2]);
    }
  }
  if (static_cast<int>(depths.size()) < params.min_valid_points) return std::nullopt;
  // The range (eq. 6) at `pixel` of a point at the region's depth.
  const double ray_x = (pixel.x - intrinsics.cx) / intrinsics.fx, ray_y = (pixel.y - intrinsics.cy) / intrinsics.fy;
  LocatedPoint located;
  located.valid_points = static_cast<int>(depths.size());
  located.range_m = regionDepth(depths, samples) * std::sqrt(ray_x * ray_x + ray_y * ray_y + 1.0);
  located.position = backProject(intrinsics, pixel, located.range_m, params.depth_model);
  return located;
}

std::optional<LocatedPoint> locateBollSurface(const cv::Mat& cloud, const std::vector<cv::Point>& outline,
                                              const cv::Point2d& centre, double radius_px,
                                              const CameraIntrinsics& intrinsics, const LocatorParams& params) {
  if (cloud.empty() || cloud.type() != CV_32FC3 || outline.size() < 3) return std::nullopt;
  if (!std::isfinite(centre.x) || !std::isfinite(centre.y) || !(radius_px > 0.0) || !std::isfinite(radius_px))
    return std::nullopt;
  const cv::Rect box = cv::boundingRect(outline) & cv::Rect(0, 0, cloud.cols, cloud.rows);
  if (box.area() == 0) return std::nullopt;
  const auto ray = [&intrinsics](double u, double v) {
    const cv::Vec3d r((u - intrinsics.cx) / intrinsics.fx, (v - intrinsics.cy) / intrinsics.fy, 1.0);
    return r / cv::norm(r);
  };
  const cv::Vec3d axis = ray(centre.x, centre.y);
  // Half angle the boll's disc subtends, averaged over two directions (off the optical axis the disc is stretched).
  const double half_angle = 0.5 * (std::acos(std::min(1.0, axis.dot(ray(centre.x + radius_px, centre.y)))) +
                                   std::acos(std::min(1.0, axis.dot(ray(centre.x, centre.y + radius_px)))));
  const double sin_a = std::sin(half_angle);
  if (!(sin_a > 0.0) || sin_a >= 1.0) return std::nullopt;

  cv::Mat inside = cv::Mat::zeros(box.size(), CV_8U);
  const std::vector<std::vector<cv::Point>> one{outline};
  cv::drawContours(inside, one, 0, cv::Scalar(255), cv::FILLED, cv::LINE_8, cv::noArray(), INT_MAX, -box.tl());
  // The outline's own pixels mix the boll with what borders it: one pixel in from it, when the region is not tiny.
  if (radius_px > 4.0) cv::erode(inside, inside, cv::Mat());
  const int stride = std::max(1, static_cast<int>(std::sqrt(box.area() / 2000.0)));
  const double rim = 0.8 * sin_a;
  std::vector<double> ranges;
  std::vector<SurfaceSample> samples;
  std::vector<DomeSample> dome;
  const double to_disc = 1.0 / radius_px;
  for (int row = 0; row < box.height; row += stride) {
    const uint8_t* in = inside.ptr<uint8_t>(row);
    const cv::Vec3f* points = cloud.ptr<cv::Vec3f>(box.y + row);
    for (int col = 0; col < box.width; col += stride) {
      if (!in[col]) continue;
      const double d = pointRange(points[box.x + col]);
      if (!(d > 0.0)) continue;
      // The dome is measured on the boll's disc out to its rim (where its depth differs most from the centre's), not
      // on what else the outline takes in (a touching boll's part beyond the split).
      const double s = (box.x + col - centre.x) * to_disc, t = (box.y + row - centre.y) * to_disc;
      if (s * s + t * t <= 1.0) dome.push_back({s, t, points[box.x + col][2]});
      const double cos_t = std::min(1.0, axis.dot(ray(box.x + col, box.y + row)));
      const double sin_t = std::sqrt(std::max(0.0, 1.0 - cos_t * cos_t));
      if (sin_t > rim) continue;
      // Range of the sphere's near surface along this pixel's ray, per unit distance D of the sphere's centre.
      const double per_distance = cos_t - std::sqrt(sin_a * sin_a - sin_t * sin_t);
      ranges.push_back(d / per_distance * (1.0 - sin_a));
      samples.push_back({ray(box.x + col, box.y + row), d});
    }
  }
  if (static_cast<int>(ranges.size()) < params.min_valid_points) return std::nullopt;
  LocatedPoint located;
  located.valid_points = static_cast<int>(ranges.size());
  located.range_m = median(ranges);
  double dome_m = 0.0, dome_sigma_m = 0.0;
  // 1.5 boll radii at a depth, per unit depth: the disc's radius over the focal length.
  const double dome_reach = 1.5 * radius_px * 2.0 / (intrinsics.fx + intrinsics.fy);
  if (fitDome(dome, dome_reach, &dome_m, &dome_sigma_m)) {
    located.dome_m = dome_m;
    located.dome_sigma_m = dome_sigma_m;
  }
  cv::Point2d apex = centre;
  if (params.apex_fit) {
    // The range of the surface at the disc's centre fixes the sphere's size; its apex is then fitted.
    const double distance = located.range_m / (1.0 - sin_a);
    // A few hundred points fix three parameters well; more only cost time.
    constexpr size_t kFitSamples = 400;
    if (samples.size() > kFitSamples) {
      const size_t step = (samples.size() + kFitSamples - 1) / kFitSamples;
      for (size_t i = 0; i * step < samples.size(); ++i) samples[i] = samples[i * step];
      samples.resize((samples.size() + step - 1) / step);
    }
    if (const std::optional<Apex> fitted = fitApex(samples, centre, radius_px, distance, sin_a, intrinsics)) {
      apex = fitted->pixel;
      located.range_m = fitted->range_m;
    }
  }
  located.position = backProject(intrinsics, apex, located.range_m, params.depth_model);
  return located;
}

std::string validate(const ReachParams& params) {
  std::ostringstream error;
  if (!(params.max_depth_m > 0.0) || !std::isfinite(params.max_depth_m))
    error << "max_depth_m must be a positive number (got " << params.max_depth_m << "); ";
  if (!(params.horizontal_arm_length_m >= 0.0) || !std::isfinite(params.horizontal_arm_length_m))
    error << "horizontal_arm_length_m must be >= 0 (got " << params.horizontal_arm_length_m << "); ";
  if (!std::isfinite(params.arm_origin_x_m)) error << "arm_origin_x_m must be finite; ";
  return error.str();
}

bool isReachable(const cv::Point3d& position, const ReachParams& params) {
  return position.z > 0.0 && position.z < params.max_depth_m &&
         std::abs(position.x - params.arm_origin_x_m) <= params.horizontal_arm_length_m;
}

}  // namespace perception
}  // namespace cotton_harvester
