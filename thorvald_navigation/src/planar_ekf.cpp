#include "thorvald_navigation/planar_ekf.h"

#include <cmath>

#include <Eigen/Cholesky>

namespace thorvald_navigation {

PlanarEkf::PlanarEkf() {
  // robot_localization's default process noise diagonal for the planar entries.
  q_ << 0.05, 0.05, 0.06, 0.025, 0.025, 0.02;
  p0_ = State6::Constant(1e-9);
}

void PlanarEkf::setProcessNoise(const State6& diagonal) { q_ = diagonal; }
void PlanarEkf::setInitialCovariance(const State6& diagonal) { p0_ = diagonal; }

void PlanarEkf::reset(const thorvald_base::Pose2D& pose, double t) {
  x_.setZero();
  x_(kX) = pose.x;
  x_(kY) = pose.y;
  x_(kYaw) = thorvald_base::normalizeAngle(pose.yaw);
  p_ = p0_.asDiagonal();
  t_ = t;
  initialized_ = true;
}

bool PlanarEkf::predict(double t) {
  if (!initialized_) reset(thorvald_base::Pose2D{}, t);
  const double dt = t - t_;
  if (!(dt >= 0.0)) return false;
  if (dt == 0.0) return true;
  const double c = std::cos(x_(kYaw)), s = std::sin(x_(kYaw));
  const double vx = x_(kVx), vy = x_(kVy);
  x_(kX) += (vx * c - vy * s) * dt;
  x_(kY) += (vx * s + vy * c) * dt;
  x_(kYaw) = thorvald_base::normalizeAngle(x_(kYaw) + x_(kVyaw) * dt);
  Cov6 f = Cov6::Identity();
  f(kX, kYaw) = (-vx * s - vy * c) * dt;
  f(kX, kVx) = c * dt;
  f(kX, kVy) = -s * dt;
  f(kY, kYaw) = (vx * c - vy * s) * dt;
  f(kY, kVx) = s * dt;
  f(kY, kVy) = c * dt;
  f(kYaw, kVyaw) = dt;
  p_ = f * p_ * f.transpose();
  p_.diagonal() += q_ * dt;
  p_ = 0.5 * (p_ + p_.transpose());
  t_ = t;
  return true;
}

std::string PlanarEkf::update(const State6& z, const State6& variance, const std::array<bool, 6>& mask) {
  int m = 0;
  for (int i = 0; i < 6; ++i) {
    if (!mask[i]) continue;
    if (!std::isfinite(z(i))) return "measurement " + std::to_string(i) + " is not finite";
    if (!(variance(i) > 0.0) || !std::isfinite(variance(i)))
      return "variance " + std::to_string(i) + " must be finite and > 0";
    ++m;
  }
  if (m == 0) return "no state entry selected";
  if (!initialized_) reset(thorvald_base::Pose2D{}, t_);
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(m, 6);
  Eigen::VectorXd innovation(m);
  Eigen::MatrixXd r = Eigen::MatrixXd::Zero(m, m);
  int row = 0;
  for (int i = 0; i < 6; ++i) {
    if (!mask[i]) continue;
    h(row, i) = 1.0;
    innovation(row) = i == kYaw ? thorvald_base::normalizeAngle(z(i) - x_(i)) : z(i) - x_(i);
    r(row, row) = variance(i);
    ++row;
  }
  const Eigen::MatrixXd s = h * p_ * h.transpose() + r;
  const Eigen::MatrixXd k = p_ * h.transpose() * s.ldlt().solve(Eigen::MatrixXd::Identity(m, m));
  x_ += k * innovation;
  x_(kYaw) = thorvald_base::normalizeAngle(x_(kYaw));
  // Joseph form keeps the covariance symmetric positive semi-definite.
  const Cov6 ikh = Cov6::Identity() - k * h;
  p_ = ikh * p_ * ikh.transpose() + k * r * k.transpose();
  p_ = 0.5 * (p_ + p_.transpose());
  return {};
}

}  // namespace thorvald_navigation
