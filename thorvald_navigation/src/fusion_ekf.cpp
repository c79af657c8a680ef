#include "thorvald_navigation/fusion_ekf.h"

#include <cmath>

#include <Eigen/Geometry>

#include "thorvald_base/pose2d.h"

namespace thorvald_navigation {

const std::array<const char*, 15> kFusionStateNames = {"x",  "y",     "z",      "roll", "pitch", "yaw", "vx", "vy",
                                                       "vz", "vroll", "vpitch", "vyaw", "ax",    "ay",  "az"};

namespace {

constexpr int kOutOfPlane[] = {kFz, kFroll, kFpitch, kFvz, kFvroll, kFvpitch, kFaz};
constexpr double kPlaneVariance = 1e-9;

Eigen::Matrix3d rotation(double roll, double pitch, double yaw) {
  return (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

/// The model without the Jacobian: body velocities and accelerations rotated into the world frame, Euler angle
/// rates from body rates.
State15 step(const State15& x, double dt) {
  State15 out = x;
  const Eigen::Matrix3d r = rotation(x(kFroll), x(kFpitch), x(kFyaw));
  const Eigen::Vector3d v = x.segment<3>(kFvx), a = x.segment<3>(kFax);
  out.segment<3>(kFx) += r * (v * dt + 0.5 * a * dt * dt);
  const double cr = std::cos(x(kFroll)), sr = std::sin(x(kFroll));
  const double cp = std::cos(x(kFpitch)), tp = std::tan(x(kFpitch));
  const double p = x(kFvroll), q = x(kFvpitch), w = x(kFvyaw);
  const double safe_cp = std::abs(cp) < 1e-6 ? std::copysign(1e-6, cp) : cp;
  out(kFroll) = thorvald_base::normalizeAngle(x(kFroll) + (p + sr * tp * q + cr * tp * w) * dt);
  out(kFpitch) = thorvald_base::normalizeAngle(x(kFpitch) + (cr * q - sr * w) * dt);
  out(kFyaw) = thorvald_base::normalizeAngle(x(kFyaw) + (sr / safe_cp * q + cr / safe_cp * w) * dt);
  out.segment<3>(kFvx) += a * dt;
  return out;
}

}  // namespace

FusionEkf::FusionEkf() {
  q_ = defaultProcessNoise();
  p0_ = Cov15::Identity() * 1e-9;
}

Cov15 FusionEkf::defaultProcessNoise() {
  State15 d;
  d << 0.05, 0.05, 0.06, 0.03, 0.03, 0.06, 0.025, 0.025, 0.04, 0.01, 0.01, 0.02, 0.01, 0.01, 0.015;
  return d.asDiagonal();
}

State15 FusionEkf::propagate(const State15& x, double dt, Cov15* jacobian) {
  const State15 out = step(x, dt);
  if (jacobian) {
    // Central differences: the model is smooth and 15 states are cheap; angles differenced modulo 2 pi.
    const double h = 1e-6;
    for (int j = 0; j < kFusionStates; ++j) {
      State15 plus = x, minus = x;
      plus(j) += h;
      minus(j) -= h;
      State15 d = step(plus, dt) - step(minus, dt);
      for (int i : {kFroll, kFpitch, kFyaw}) d(i) = thorvald_base::normalizeAngle(d(i));
      jacobian->col(j) = d / (2.0 * h);
    }
  }
  return out;
}

void FusionEkf::reset(const State15& state, double t) {
  x_ = state;
  for (int i : {kFroll, kFpitch, kFyaw}) x_(i) = thorvald_base::normalizeAngle(x_(i));
  p_ = p0_;
  t_ = t;
  initialized_ = true;
  holdPlane();
}

bool FusionEkf::predict(double t) {
  if (!initialized_) reset(State15::Zero(), t);
  const double dt = t - t_;
  if (!(dt >= 0.0)) return false;
  if (dt == 0.0) return true;
  Cov15 f;
  x_ = propagate(x_, dt, &f);
  p_ = f * p_ * f.transpose() + q_ * dt;
  p_ = 0.5 * (p_ + p_.transpose());
  t_ = t;
  holdPlane();
  return true;
}

UpdateResult FusionEkf::update(const std::vector<MeasuredEntry>& z, double gate_sigma) {
  std::vector<MeasuredEntry> used;
  for (const MeasuredEntry& e : z) {
    bool out_of_plane = false;
    for (int i : kOutOfPlane) out_of_plane = out_of_plane || e.index == i;
    if (!(two_d_ && out_of_plane)) used.push_back(e);
  }
  State15 x = initialized_ ? x_ : State15::Zero();
  Cov15 p = initialized_ ? p_ : p0_;
  const UpdateResult r = kalmanUpdate(x, p, used, {kFroll, kFpitch, kFyaw}, gate_sigma);
  if (!r.fused()) return r;
  initialized_ = true;
  x_ = x;
  p_ = p;
  holdPlane();
  return r;
}

void FusionEkf::holdPlane() {
  if (!two_d_) return;
  for (int i : kOutOfPlane) {
    x_(i) = 0.0;
    p_.row(i).setZero();
    p_.col(i).setZero();
    p_(i, i) = kPlaneVariance;
  }
}

}  // namespace thorvald_navigation
