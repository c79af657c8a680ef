#pragma once

#include <Eigen/Core>

#include "thorvald_base/pose2d.h"
#include "thorvald_base/twist2d.h"

namespace thorvald_base {

/// Integrates body twists into a pose (base_link in odom), exactly along the arc a constant twist describes, and
/// propagates the pose covariance from the twist covariance. Also sums the distance travelled.
class OdometryIntegrator {
 public:
  /// Advances by `dt_s` [s] at `twist` with covariance `twist_cov` (vx, vy, wz).
  void integrate(const Twist2D& twist, const Eigen::Matrix3d& twist_cov, double dt_s);
  void reset();
  const Pose2D& pose() const { return pose_; }
  const Eigen::Matrix3d& covariance() const { return covariance_; }
  double distance() const { return distance_m_; }

 private:
  Pose2D pose_;
  Eigen::Matrix3d covariance_ = Eigen::Matrix3d::Zero();
  double distance_m_ = 0.0;
};

}  // namespace thorvald_base
