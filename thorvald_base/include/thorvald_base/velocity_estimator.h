#pragma once

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "thorvald_base/twist2d.h"

namespace thorvald_base {

/// What one wheel tells about the body's motion: where it is, which way it rolls, and how fast.
struct WheelObservation {
  double x = 0.0, y = 0.0;   ///< contact point in base_link [m]
  double heading_rad = 0.0;  ///< rolling direction in base_link [rad]
  double speed_mps = 0.0;    ///< ground speed along the heading [m/s]
  bool has_speed = true;     ///< false for passive wheels: only "no sideways motion" is known
};

/// A body twist estimated from wheel observations, with its covariance (vx, vy, wz).
struct VelocityEstimate {
  Twist2D twist;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity() * 1e-3;
  bool valid = false;
};

/// Estimates the body twist from the wheels. Implementations are stateless apart from a seeded generator.
class VelocityEstimator {
 public:
  virtual ~VelocityEstimator() = default;
  virtual VelocityEstimate estimate(const std::vector<WheelObservation>& wheels) = 0;
  virtual std::string name() const = 0;
};

/// Least-squares rigid-body fit of (vx, vy, wz) to every wheel's rolling and no-sideways-motion equations,
/// re-weighted (Huber) so a slipping wheel counts less. Needs no special case for straight driving.
class LeastSquaresEstimator : public VelocityEstimator {
 public:
  /// huber_mps: residual [m/s] above which an equation is down-weighted.
  explicit LeastSquaresEstimator(double huber_mps = 0.02, int iterations = 3);
  VelocityEstimate estimate(const std::vector<WheelObservation>& wheels) override;
  std::string name() const override { return "least_squares"; }

 private:
  double huber_mps_;
  int iterations_;
};

/// The Thorvald paper's estimator (§3.3.1): wheels paired at random (seeded), the intersections of the lines
/// normal to each pair averaged as the centre of rotation, the rotation rate from it and the wheel speeds.
/// Parallel wheels (no intersection) mean translation.
class RandomPairsEstimator : public VelocityEstimator {
 public:
  RandomPairsEstimator(unsigned seed = 1, int pairs = 20);
  VelocityEstimate estimate(const std::vector<WheelObservation>& wheels) override;
  std::string name() const override { return "random_pairs"; }

 private:
  unsigned state_;
  int pairs_;
  unsigned next();
};

/// Makes an estimator by name ("least_squares" or "random_pairs"); nullptr for an unknown name.
std::unique_ptr<VelocityEstimator> makeVelocityEstimator(const std::string& name, unsigned seed = 1);

}  // namespace thorvald_base
