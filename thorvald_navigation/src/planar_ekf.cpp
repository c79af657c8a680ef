#include "thorvald_navigation/planar_ekf.h"

#include <limits>

#include <cmath>
#include <vector>

#include "thorvald_navigation/ekf_update.h"

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
  return update(z, variance, mask, std::numeric_limits<double>::infinity()).error;
}

UpdateResult PlanarEkf::update(const State6& z, const State6& variance, const std::array<bool, 6>& mask,
                               double gate_sigma) {
  std::vector<MeasuredEntry> entries;
  for (int i = 0; i < 6; ++i)
    if (mask[i]) entries.push_back({i, z(i), variance(i)});
  // A first measurement starts the filter at the origin; a refused one leaves it as it was.
  State6 x = initialized_ ? x_ : State6::Zero();
  Cov6 p = initialized_ ? p_ : Cov6(p0_.asDiagonal());
  // No gate before the filter has started: nothing to compare with.
  const UpdateResult result =
      kalmanUpdate(x, p, entries, {kYaw}, initialized_ ? gate_sigma : std::numeric_limits<double>::infinity());
  if (!result.fused()) return result;
  initialized_ = true;
  x_ = x;
  p_ = p;
  return result;
}

}  // namespace thorvald_navigation
