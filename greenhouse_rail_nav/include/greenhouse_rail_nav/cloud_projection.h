#pragma once

#include <optional>

#include <Eigen/Core>

#include "greenhouse_rail_nav/depth_camera.h"

namespace greenhouse_rail_nav {

/// The pinhole projection of an organised cloud, recovered from the cloud itself: a finite point of
/// pixel (u, v) lies on the ray (x/z, y/z) = ((u - cx) / fx, (v - cy) / fy). Knowing it, the detector can
/// tell whether a point of the scene (the rails' start) lies inside the image, without a CameraInfo.
class CloudProjection {
 public:
  /// Fits fx, cx and fy, cy by least squares on a grid of the cloud's finite points (every `stride`-th
  /// row and column). Empty when fewer than 20 points are usable, when they do not span the image, or
  /// when the fit leaves more than max_rms_px of residual (not a pinhole organised cloud).
  static std::optional<CloudProjection> fromCloud(const OrganisedCloud& cloud, int stride = 8, double max_rms_px = 1.0);

  explicit CloudProjection(const DepthCameraIntrinsics& k) : k_(k) {}

  /// True when the point (optical frame [m]) is in front of the camera and projects at least margin_px
  /// inside the image border.
  bool inImage(const Eigen::Vector3d& point, double margin_px) const;

  const DepthCameraIntrinsics& intrinsics() const { return k_; }

 private:
  DepthCameraIntrinsics k_;
};

}  // namespace greenhouse_rail_nav
