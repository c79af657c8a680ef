#pragma once

#include <optional>
#include <string>

#include <opencv2/core.hpp>

namespace cotton_harvester {
namespace perception {

/// Pinhole intrinsics of the left lens. Defaults: the paper's ZED calibration at 1280x720 (eq. 1).
struct CameraIntrinsics {
  double fx = 699.936;  ///< focal length [px]
  double fy = 699.936;  ///< focal length [px]
  double cx = 685.286;  ///< optical centre column [px]
  double cy = 361.248;  ///< optical centre row [px]
  int width = 1280;     ///< image width [px]
  int height = 720;     ///< image height [px]
};

/// How the depth read from the point cloud becomes a camera-frame point.
enum class DepthModel {
  /// The range of eq. 6 is taken along the pixel's viewing ray: the point is range * unit ray. Exact for a
  /// pinhole camera; this is the default.
  kRay,
  /// The paper's eqs. 4-6 literally: Wz = range, Wx = (Ix - Cx) Wz / fx, Wy = (Iy - Cy) Wz / fy (with the
  /// pinhole sign I - C; the paper prints I + C). Overestimates |Wx|, |Wy| and Wz off the optical axis.
  kPaper,
};

/// Parses "ray" or "paper"; std::nullopt for anything else.
std::optional<DepthModel> parseDepthModel(const std::string& name);
std::string toString(DepthModel model);

/// Checks the intrinsics; returns an empty string when valid, otherwise what is wrong.
std::string validate(const CameraIntrinsics& intrinsics);

/// The same lens at another image size (a camera mode that scales the sensor): fx, cx by width / old width,
/// fy, cy by height / old height.
CameraIntrinsics scaledTo(const CameraIntrinsics& intrinsics, int width, int height);

/// Projects a camera-frame point (x right, y down, z along the optical axis) [m] to a pixel [px].
/// Requires point.z > 0.
cv::Point2d project(const CameraIntrinsics& intrinsics, const cv::Point3d& point);

/// Euclidean distance of a point from the lens (eq. 6) [m].
double range(const cv::Point3d& point);

/// Turns a pixel [px] and its range from the lens [m] (eq. 6) into a camera-frame point [m].
cv::Point3d backProject(const CameraIntrinsics& intrinsics, const cv::Point2d& pixel, double range_m, DepthModel model);

}  // namespace perception
}  // namespace cotton_harvester
