#pragma once

#include <cmath>
#include <vector>

#include <Eigen/Geometry>

namespace greenhouse_rail_nav {

/// Pinhole intrinsics of a depth camera [px].
struct DepthCameraIntrinsics {
  int width = 640;
  int height = 480;
  double fx = 457.0, fy = 457.0;  ///< focal lengths [px]: about 70 deg horizontal field of view at 640 px
  double cx = 319.5, cy = 239.5;  ///< principal point [px]

  /// Same field of view at another resolution.
  DepthCameraIntrinsics scaled(int new_width, int new_height) const {
    DepthCameraIntrinsics k = *this;
    const double sx = static_cast<double>(new_width) / width, sy = static_cast<double>(new_height) / height;
    k.width = new_width;
    k.height = new_height;
    k.fx = fx * sx;
    k.fy = fy * sy;
    k.cx = (cx + 0.5) * sx - 0.5;
    k.cy = (cy + 0.5) * sy - 0.5;
    return k;
  }
};

/// Pose of the camera's optical frame (z forward, x right, y down) in base_link for a camera at
/// (x, y, z) [m] looking forward and pitched down by pitch_rad.
inline Eigen::Isometry3d opticalFrameInBase(double x_m, double y_m, double z_m, double pitch_rad,
                                            double yaw_rad = 0.0) {
  Eigen::Matrix3d axes;  // columns: optical x, y, z in a level, forward-looking body frame
  axes << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() =
      (Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch_rad, Eigen::Vector3d::UnitY()))
          .toRotationMatrix() *
      axes;
  t.translation() = Eigen::Vector3d(x_m, y_m, z_m);
  return t;
}

/// An organised cloud: width x height points in the camera's optical frame [m], NaN where no depth.
struct OrganisedCloud {
  int width = 0;
  int height = 0;
  std::vector<Eigen::Vector3f> points;
};

}  // namespace greenhouse_rail_nav
