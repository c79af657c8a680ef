#pragma once

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "cotton_harvester/perception/camera_model.h"

namespace cotton_harvester {
namespace perception {

/// How a pixel's depth is read from the organised point cloud.
struct LocatorParams {
  /// Side of the square window around the pixel whose valid points are used [px], odd, >= 1. The median range
  /// of the window's valid points is taken, so stereo holes and a few background points do not matter.
  int window_px = 5;
  /// Fewest valid (finite, non-zero) points the window must hold [-].
  int min_valid_points = 3;
  DepthModel depth_model = DepthModel::kRay;
  /// Bolls whose detector estimates their disc (ColourBollDetector) are located from their visible surface at the
  /// disc's centre (locateBollSurface); false: the window around the visible centroid, as for box detectors.
  bool boll_surface = true;
  /// With boll_surface: the surface point nearest the lens (on the ray through the boll's centre) is fitted to the
  /// visible surface's ranges instead of taken at the centre of the white disc, which lies off that ray where the
  /// white lint covers the boll's top rather than the side facing the camera. Needs a depth noise that is not
  /// correlated over the whole boll (see the package README).
  bool apex_fit = true;
};

std::string validate(const LocatorParams& params);

/// A pixel located in 3D.
struct LocatedPoint {
  cv::Point3d position;  ///< camera frame: x right, y down, z along the optical axis [m]
  double range_m = 0.0;  ///< distance from the left lens, eq. 6 [m]
  int valid_points = 0;  ///< valid cloud points used [-]
  /// locateBollSurface only: how far the visible surface bulges towards the camera, the depth of the disc's rim
  /// below its centre [m] after a tilted plane is taken out (BollDome), and its standard error [m]; NaN when not
  /// measured (too few points, or not a boll's surface).
  double dome_m = std::numeric_limits<double>::quiet_NaN();
  double dome_sigma_m = std::numeric_limits<double>::quiet_NaN();
};

/// Locates an image point in 3D (paper §2.8): its range from the lens (eq. 6) is the median over the window of
/// sqrt(dx^2 + dy^2 + dz^2) of the organised cloud's points; x and y come from the intrinsics (pinhole, I - C).
/// cloud: CV_32FC3, one camera-frame point [m] per pixel, NaN where the stereo matcher found none.
/// Returns std::nullopt when the pixel is outside the cloud or the window has too few valid points.
std::optional<LocatedPoint> locate(const cv::Mat& cloud, const cv::Point2d& pixel, const CameraIntrinsics& intrinsics,
                                   const LocatorParams& params);

/// Locates a segmented region (the end-effector): its depth is the median depth (z) of the valid cloud points
/// under the mask (non-zero pixels, CV_8U, the cloud's size), so a leaf over part of the region does not lend it
/// its depth; the range at `pixel` of a point at that depth then goes through the depth model as in locate().
/// When fewer than half the mask's pixels carry depth (a passive-stereo camera finds no match on a uniform or
/// saturated face: the housing's top in sun), what carries depth is the face's rim and the sides below it, which lie
/// deeper than the face: the depth is then the median of the nearest quarter of the valid depths.
/// std::nullopt when the mask holds fewer than min_valid_points valid points or does not fit the cloud.
std::optional<LocatedPoint> locateRegion(const cv::Mat& cloud, const cv::Mat& mask, const cv::Point2d& pixel,
                                         const CameraIntrinsics& intrinsics, const LocatorParams& params);

/// Locates a boll from the visible part of its surface: the boll is a sphere whose image is the disc (centre,
/// radius_px) and of which the pixels inside `outline` (image pixels, a closed contour) are visible. Every valid
/// cloud point under the outline, away from the rim (within 0.8 of the disc's radius), gives through the sphere's
/// shape the range of the surface point on the ray through the disc's centre (a point seen at angle t from the
/// centre's ray lies deeper than that point: its range is D (cos t - sqrt(sin^2 a - sin^2 t)) for a sphere at
/// distance D whose disc subtends the half angle a); the median of these is taken, so points of a leaf edge or of
/// the ground that the outline takes in do not matter. This reads the boll's depth where it is visible even when its
/// centre is hidden, and averages the stereo noise of many points instead of a small window's. The returned
/// position is that surface point on the centre's ray (the centre lies one boll radius deeper along it).
/// The valid points under the outline that lie on the disc (out to its rim) also measure the surface's dome
/// (LocatedPoint::dome_m): their depths are fitted with
/// z = z0 + b s + c t + h (s^2 + t^2), where (s, t) is the pixel's offset from the disc's centre in disc radii, so h is
/// how much deeper the disc's rim lies than its centre once any tilt is taken out. A sphere of radius R gives
/// h ~ 0.5 R (the white part seen from above); a label, a flat fold of a bag or a bar lying in any plane gives
/// h ~ 0. Only points within 1.5 boll radii (radius_px at their median depth) of their median depth are fitted: a
/// sphere's visible cap spans less than its radius in depth, so what lies farther is another surface under the
/// outline (a boll in front of or behind a boll that touches it in the image, a leaf, the ground). Points more than 3
/// robust sigmas off the first fit are left out of the second; fewer than 12 points or a singular fit leave dome_m
/// NaN.
/// std::nullopt when fewer than min_valid_points valid points lie under the outline, or on bad input (empty or
/// non-CV_32FC3 cloud, non-finite centre, radius <= 0, outline outside the cloud).
std::optional<LocatedPoint> locateBollSurface(const cv::Mat& cloud, const std::vector<cv::Point>& outline,
                                              const cv::Point2d& centre, double radius_px,
                                              const CameraIntrinsics& intrinsics, const LocatorParams& params);

/// The manipulator's workspace as seen from the camera (paper §2.8).
struct ReachParams {
  /// Distance from the camera down to the end-effector's lowest position [m]: the camera is 2.20 m above the
  /// ground and the manipulator keeps 0.27 m of ground clearance.
  double max_depth_m = 1.93;
  /// Length of the horizontal axis arm [m] (§2.1: 70 cm).
  double horizontal_arm_length_m = 0.70;
  /// Camera-frame x of the line the horizontal offset is measured from [m] (the camera centre in the paper).
  double arm_origin_x_m = 0.0;
};

std::string validate(const ReachParams& params);

/// A boll is reachable when 0 < z < max_depth_m and |x - arm_origin_x_m| <= horizontal_arm_length_m.
bool isReachable(const cv::Point3d& position, const ReachParams& params);

}  // namespace perception
}  // namespace cotton_harvester
