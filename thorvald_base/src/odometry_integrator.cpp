#include "thorvald_base/odometry_integrator.h"

#include <Eigen/Dense>
#include <cmath>

#include "thorvald_base/angles.h"

namespace thorvald_base {

void OdometryIntegrator::integrate(const Twist2D& t, const Eigen::Matrix3d& twist_cov, double dt) {
  if (!(dt > 0.0) || !t.finite()) return;
  const double dtheta = t.wz * dt;
  double dx = t.vx * dt, dy = t.vy * dt;  // displacement in the body frame at the start of the step
  if (std::fabs(dtheta) > 1e-9) {
    const double s = std::sin(dtheta), c = std::cos(dtheta);
    dx = (t.vx * s + t.vy * (c - 1.0)) / t.wz;
    dy = (t.vx * (1.0 - c) + t.vy * s) / t.wz;
  }
  const double cy = std::cos(pose_.yaw), sy = std::sin(pose_.yaw);
  const double wx = cy * dx - sy * dy, wy = sy * dx + cy * dy;

  Eigen::Matrix3d f = Eigen::Matrix3d::Identity();  // d(new pose)/d(old pose)
  f(0, 2) = -wy;
  f(1, 2) = wx;
  Eigen::Matrix3d g = Eigen::Matrix3d::Zero();  // d(new pose)/d(twist), first order
  g(0, 0) = cy * dt;
  g(0, 1) = -sy * dt;
  g(1, 0) = sy * dt;
  g(1, 1) = cy * dt;
  g(2, 2) = dt;
  covariance_ = f * covariance_ * f.transpose() + g * twist_cov * g.transpose();

  pose_.x += wx;
  pose_.y += wy;
  pose_.yaw = normalizeAngle(pose_.yaw + dtheta);
  distance_m_ += std::hypot(t.vx, t.vy) * dt;  // path length along the arc
}

void OdometryIntegrator::reset() { *this = OdometryIntegrator(); }

}  // namespace thorvald_base
