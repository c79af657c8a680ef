#include "cotton_harvester/perception/camera_model.h"

#include <cmath>
#include <sstream>

namespace cotton_harvester {
namespace perception {

std::optional<DepthModel> parseDepthModel(const std::string& name) {
  if (name == "ray") return DepthModel::kRay;
  if (name == "paper") return DepthModel::kPaper;
  return std::nullopt;
}

std::string toString(DepthModel model) { return model == DepthModel::kRay ? "ray" : "paper"; }

std::string validate(const CameraIntrinsics& intrinsics) {
  std::ostringstream error;
  if (!(intrinsics.fx > 0.0) || !std::isfinite(intrinsics.fx)) error << "fx must be a positive number; ";
  if (!(intrinsics.fy > 0.0) || !std::isfinite(intrinsics.fy)) error << "fy must be a positive number; ";
  if (!std::isfinite(intrinsics.cx)) error << "cx must be finite; ";
  if (!std::isfinite(intrinsics.cy)) error << "cy must be finite; ";
  if (intrinsics.width <= 0) error << "width must be > 0; ";
  if (intrinsics.height <= 0) error << "height must be > 0; ";
  return error.str();
}

CameraIntrinsics scaledTo(const CameraIntrinsics& intrinsics, int width, int height) {
  CameraIntrinsics scaled = intrinsics;
  const double sx = static_cast<double>(width) / intrinsics.width, sy = static_cast<double>(height) / intrinsics.height;
  scaled.fx *= sx;
  scaled.cx *= sx;
  scaled.fy *= sy;
  scaled.cy *= sy;
  scaled.width = width;
  scaled.height = height;
  return scaled;
}

cv::Point2d project(const CameraIntrinsics& intrinsics, const cv::Point3d& point) {
  return {intrinsics.fx * point.x / point.z + intrinsics.cx, intrinsics.fy * point.y / point.z + intrinsics.cy};
}

double range(const cv::Point3d& point) { return std::sqrt(point.dot(point)); }

cv::Point3d backProject(const CameraIntrinsics& intrinsics, const cv::Point2d& pixel, double range_m,
                        DepthModel model) {
  // Pinhole: I = f W / Wz + C, hence W = (I - C) Wz / f.
  const double ray_x = (pixel.x - intrinsics.cx) / intrinsics.fx;
  const double ray_y = (pixel.y - intrinsics.cy) / intrinsics.fy;
  if (model == DepthModel::kPaper) return {ray_x * range_m, ray_y * range_m, range_m};
  const double z = range_m / std::sqrt(ray_x * ray_x + ray_y * ray_y + 1.0);
  return {ray_x * z, ray_y * z, z};
}

}  // namespace perception
}  // namespace cotton_harvester
