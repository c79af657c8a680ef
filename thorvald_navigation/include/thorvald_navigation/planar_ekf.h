#pragma once

#include <array>
#include <string>

#include <Eigen/Core>

#include "thorvald_base/pose2d.h"
#include "thorvald_navigation/ekf_update.h"

namespace thorvald_navigation {

/// Indices of the planar state: pose in the odometry frame, velocity in base_link.
enum StateIndex { kX = 0, kY = 1, kYaw = 2, kVx = 3, kVy = 4, kVyaw = 5 };
using State6 = Eigen::Matrix<double, 6, 1>;
using Cov6 = Eigen::Matrix<double, 6, 6>;

/// Extended Kalman filter on (x, y, yaw, vx, vy, vyaw) with a constant-velocity model, for fusing wheel odometry
/// twists with a gyro's yaw rate and an absolute yaw. Process noise is a rate (per second), scaled by the
/// prediction step as robot_localization does. Measurements select any subset of the state; non-finite input is
/// rejected with the reason and leaves the filter untouched.
class PlanarEkf {
 public:
  PlanarEkf();

  /// Process noise density: diagonal entries for (x, y, yaw, vx, vy, vyaw) [unit^2/s].
  void setProcessNoise(const State6& diagonal);
  void setInitialCovariance(const State6& diagonal);
  /// Starts over at `pose`, at rest, with the initial covariance, at time `t` [s].
  void reset(const thorvald_base::Pose2D& pose, double t);

  /// Moves the state to time `t` [s]; a `t` before the current time is ignored (returns false).
  bool predict(double t);
  /// Fuses the entries `mask` selects from `z` with variances `variance` (each > 0). Angles are compared modulo
  /// 2 pi. Returns an empty string when fused, else why it was rejected.
  std::string update(const State6& z, const State6& variance, const std::array<bool, 6>& mask);
  /// The same behind a Mahalanobis gate of `gate_sigma` standard deviations (robot_localization's
  /// *_rejection_threshold; infinity: none): a measurement that far from the prediction is refused (`gated`).
  UpdateResult update(const State6& z, const State6& variance, const std::array<bool, 6>& mask, double gate_sigma);

  bool initialized() const { return initialized_; }
  double time() const { return t_; }
  const State6& state() const { return x_; }
  const Cov6& covariance() const { return p_; }
  thorvald_base::Pose2D pose() const { return {x_(kX), x_(kY), x_(kYaw)}; }

 private:
  State6 x_ = State6::Zero();
  Cov6 p_ = Cov6::Identity();
  State6 q_;
  State6 p0_;
  double t_ = 0.0;
  bool initialized_ = false;
};

}  // namespace thorvald_navigation
