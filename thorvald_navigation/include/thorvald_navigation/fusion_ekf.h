#pragma once

#include <array>
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "thorvald_navigation/ekf_update.h"

namespace thorvald_navigation {

/// robot_localization's 15-entry state and sensor configuration order.
enum Fusion15 {
  kFx = 0,
  kFy,
  kFz,
  kFroll,
  kFpitch,
  kFyaw,
  kFvx,
  kFvy,
  kFvz,
  kFvroll,
  kFvpitch,
  kFvyaw,
  kFax,
  kFay,
  kFaz
};
constexpr int kFusionStates = 15;
using State15 = Eigen::Matrix<double, 15, 1>;
using Cov15 = Eigen::Matrix<double, 15, 15>;
/// Names of the 15 entries in order ("x" ... "az"), as robot_localization's documentation lists them.
extern const std::array<const char*, 15> kFusionStateNames;

/// Extended Kalman filter on robot_localization's 15-entry state: pose (x y z roll pitch yaw) in the world frame,
/// velocities (vx vy vz vroll vpitch vyaw) and accelerations (ax ay az) in base_link, with its constant-
/// acceleration model. Process noise is a rate (per second), scaled by the prediction step as robot_localization
/// does. In two-D mode z, roll, pitch, their rates and az are held at zero with a negligible variance, so the
/// filter is the planar one (same maths as PlanarEkf: the shared kalmanUpdate). Measurements observe any subset
/// of the state directly; a Mahalanobis gate may refuse them; a refused measurement leaves the filter untouched.
class FusionEkf {
 public:
  FusionEkf();

  /// robot_localization's defaults: process noise diagonal [unit^2/s] and 1e-9 initial covariance.
  static Cov15 defaultProcessNoise();

  void setProcessNoise(const Cov15& q) { q_ = q; }
  void setInitialCovariance(const Cov15& p0) { p0_ = p0; }
  void setTwoDMode(bool on) { two_d_ = on; }
  bool twoDMode() const { return two_d_; }

  /// Starts over at `state` (velocities and accelerations included) with the initial covariance at time t [s].
  void reset(const State15& state, double t);
  /// Moves the state to time `t` [s]; a `t` before the current time is refused (false).
  bool predict(double t);
  /// Fuses the measured entries (angles modulo 2 pi). `gate_sigma`: Mahalanobis gate, infinity for none.
  UpdateResult update(const std::vector<MeasuredEntry>& z, double gate_sigma = std::numeric_limits<double>::infinity());

  bool initialized() const { return initialized_; }
  double time() const { return t_; }
  const State15& state() const { return x_; }
  const Cov15& covariance() const { return p_; }

  /// The motion model over `dt` [s] (exposed for tests): the state after dt and its Jacobian.
  static State15 propagate(const State15& x, double dt, Cov15* jacobian = nullptr);

 private:
  void holdPlane();

  State15 x_ = State15::Zero();
  Cov15 p_ = Cov15::Identity() * 1e-9;
  Cov15 q_;
  Cov15 p0_;
  double t_ = 0.0;
  bool two_d_ = false;
  bool initialized_ = false;
};

}  // namespace thorvald_navigation
