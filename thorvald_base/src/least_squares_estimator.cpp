#include <Eigen/Dense>
#include <cmath>

#include "thorvald_base/velocity_estimator.h"

namespace thorvald_base {

LeastSquaresEstimator::LeastSquaresEstimator(double huber_mps, int iterations)
    : huber_mps_(huber_mps), iterations_(iterations) {}

VelocityEstimate LeastSquaresEstimator::estimate(const std::vector<WheelObservation>& wheels) {
  // Each wheel: its rolling equation (velocity of the contact point along the heading = measured speed) and,
  // for every wheel, its no-sideways-motion equation. Unknowns (vx, vy, wz) of base_link.
  const int rows = static_cast<int>(2 * wheels.size());
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(rows, 3);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(rows);
  Eigen::VectorXd used = Eigen::VectorXd::Zero(rows);
  int r = 0;
  for (const auto& w : wheels) {
    const double c = std::cos(w.heading_rad), s = std::sin(w.heading_rad);
    if (w.has_speed && std::isfinite(w.speed_mps)) {
      a.row(r) << c, s, -w.y * c + w.x * s;
      b(r) = w.speed_mps;
      used(r) = 1.0;
    }
    ++r;
    a.row(r) << -s, c, w.y * s + w.x * c;
    used(r) = 1.0;
    ++r;
  }
  VelocityEstimate out;
  const int equations = static_cast<int>(used.sum());
  if (equations == 0) return out;

  Eigen::VectorXd weight = used;
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
  for (int it = 0; it <= iterations_; ++it) {
    const Eigen::MatrixXd aw = weight.asDiagonal() * a;
    normal = a.transpose() * aw;
    // Complete orthogonal decomposition: the minimum-norm solution when wheels leave a direction unobserved.
    x = normal.completeOrthogonalDecomposition().solve(aw.transpose() * b);
    if (it == iterations_) break;
    const Eigen::VectorXd residual = a * x - b;
    for (int i = 0; i < rows; ++i) {
      if (used(i) == 0.0) continue;
      const double e = std::fabs(residual(i));
      weight(i) = e <= huber_mps_ ? 1.0 : huber_mps_ / e;
    }
  }
  const Eigen::VectorXd residual = a * x - b;
  double sse = 0.0, wsum = 0.0;
  for (int i = 0; i < rows; ++i) {
    sse += weight(i) * residual(i) * residual(i);
    wsum += weight(i);
  }
  const double dof = std::max(1.0, wsum - 3.0);
  const double sigma2 = std::max(sse / dof, 1e-6);  // floor: encoder resolution is never perfect
  out.twist = {x(0), x(1), x(2)};
  auto decomposition = normal.completeOrthogonalDecomposition();
  out.covariance = sigma2 * decomposition.pseudoInverse();
  // Wheels that leave a direction of (vx, vy, wz) unobserved (e.g. one drive left online) give no estimate: a
  // minimum-norm guess would report "no motion" with a small covariance while the robot moves.
  decomposition.setThreshold(1e-9);
  out.valid = out.twist.finite() && decomposition.rank() == 3;
  return out;
}

}  // namespace thorvald_base
