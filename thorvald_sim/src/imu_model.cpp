#include "thorvald_sim/imu_model.h"

#include <cmath>

namespace thorvald_sim {

namespace {

Eigen::Vector3d normal3(std::mt19937& rng) {
  std::normal_distribution<double> unit(0.0, 1.0);
  const double x = unit(rng), y = unit(rng), z = unit(rng);  // one statement each: the order of draws is fixed
  return {x, y, z};
}

}  // namespace

ImuModel um7ImuModel() {
  constexpr double kDeg = M_PI / 180.0;
  ImuModel m;
  m.gyro = {0.1 * kDeg, 0.01 * kDeg, 1000.0, 2e-5, 0.01};
  m.accel = {0.035, 0.005, 300.0, 1e-4, 0.01};
  return m;
}

ImuModel phidget1044ImuModel() {
  constexpr double kDeg = M_PI / 180.0, kG = 9.80665;
  ImuModel m;
  m.gyro = {0.095 * kDeg, 0.0042 * kDeg, 7743.0, 0.0, 0.005};
  m.accel = {280e-6 * kG, 40.6e-6 * kG, 398.0, 0.0, 0.005};
  return m;
}

ImuErrors::Triad::Triad(const ImuTriadModel& m, std::mt19937& rng) : m_(m), walk_(Eigen::Vector3d::Zero()) {
  scale_ = Eigen::Vector3d::Ones() + m.scale_factor_sigma * normal3(rng);
  markov_ = m.bias_instability * normal3(rng);
}

Eigen::Vector3d ImuErrors::Triad::read(const Eigen::Vector3d& truth, double dt, std::mt19937& rng) {
  if (dt > 0.0) {
    // Exact discretisation of the first-order Gauss-Markov process: its variance stays bias_instability^2.
    const double phi = std::exp(-dt / m_.bias_correlation_s);
    markov_ = phi * markov_ + m_.bias_instability * std::sqrt(1.0 - phi * phi) * normal3(rng);
    walk_ += m_.bias_random_walk * std::sqrt(dt) * normal3(rng);
  }
  return scale_.cwiseProduct(truth) + markov_ + walk_ + m_.white_sigma * normal3(rng);
}

ImuErrors::ImuErrors(const ImuModel& model, std::mt19937& rng) : gyro_(model.gyro, rng), accel_(model.accel, rng) {}

void ImuErrors::apply(double t_s, Eigen::Vector3d* gyro_radps, Eigen::Vector3d* accel_mps2, std::mt19937& rng) {
  const double dt = started_ ? std::max(0.0, t_s - last_t_) : 0.0;
  started_ = true;
  last_t_ = std::max(last_t_, t_s);
  *gyro_radps = gyro_.read(*gyro_radps, dt, rng);
  *accel_mps2 = accel_.read(*accel_mps2, dt, rng);
}

}  // namespace thorvald_sim
