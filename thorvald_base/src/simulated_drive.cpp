#include "thorvald_base/simulated_drive.h"

#include <algorithm>
#include <cmath>

#include "thorvald_base/angles.h"

namespace thorvald_base {
namespace {
constexpr double kMaxStep_s = 0.005;  // integration sub-step, so slow update rates still ramp correctly
constexpr double kHomingTime_s = 2.0;
}  // namespace

SimulatedDrive::SimulatedDrive(const DriveConfig& config, const SimulatedDriveOptions& options)
    : config_(config), options_(options), rng_(options.seed) {
  read();
}

void SimulatedDrive::reconfigure(const DriveConfig& config) { config_ = config; }

bool SimulatedDrive::startHoming() {
  if (!config_.steered()) return false;
  homing_until_ = std::max(last_time_, 0.0) + kHomingTime_s;
  return true;
}

DriveStatus SimulatedDrive::status() const {
  DriveStatus s;
  s.fault = fault_;
  s.homing = last_time_ < homing_until_;
  s.text = fault_ ? "simulated fault" : (s.homing ? "homing steering" : "ok");
  return s;
}

void SimulatedDrive::update(double now_s) {
  if (last_time_ < 0.0) last_time_ = now_s;
  double dt = now_s - last_time_;
  if (dt < 0.0) dt = 0.0;  // a clock that jumps back (a reset simulation) does not run time backwards
  last_time_ = now_s;
  while (dt > 1e-12) {
    const double h = std::min(dt, kMaxStep_s);
    step(h);
    dt -= h;
  }
  if (options_.slip_fraction > 0.0 && options_.slip_period_s > 0.0) {
    const long period = static_cast<long>(std::floor(now_s / options_.slip_period_s));
    if (period != slip_period_index_) {
      slip_period_index_ = period;
      slipping_ = std::uniform_real_distribution<double>(0.0, 1.0)(rng_) < options_.slip_fraction;
    }
  }
  read();
}

void SimulatedDrive::step(double dt) {
  const bool homing = last_time_ < homing_until_;
  const double target_speed = (fault_ || homing) ? 0.0 : command_.wheel_speed_radps;
  const double max_dw = config_.prp_sim_a / config_.r_wheel * dt;
  wheel_speed_ += std::clamp(target_speed - wheel_speed_, -max_dw, max_dw);
  wheel_position_ += wheel_speed_ * dt;
  if (slipping_) slip_position_extra_ += options_.slip_ratio * wheel_speed_ * dt;
  if (config_.steered()) {
    const double target = homing ? 0.0 : std::clamp(command_.steering_rad, -config_.str_lim, config_.str_lim);
    const double max_ds = config_.str_sim_v * dt;
    const double ds = std::clamp(target - steering_, -max_ds, max_ds);
    steering_ += ds;
    steering_speed_ = ds / dt;
  }
}

void SimulatedDrive::read() {
  // The wheel turns at wheel_speed_ but rolls wheel_speed_ * r_true; odometry believes r_wheel. A radius error
  // therefore shows as a wrong ground speed, which is what the estimators must live with.
  double speed = wheel_speed_ * (slipping_ ? 1.0 + options_.slip_ratio : 1.0);
  double position = wheel_position_ + slip_position_extra_;
  double steering = steering_;
  if (options_.speed_noise_radps > 0.0)
    speed += std::normal_distribution<double>(0.0, options_.speed_noise_radps)(rng_);
  if (options_.steering_noise_rad > 0.0) {
    steering += std::normal_distribution<double>(0.0, options_.steering_noise_rad)(rng_);
  }
  if (options_.quantize) {
    // Speed is reported as integer motor rpm; positions as quadrature encoder counts (4 per pulse).
    const double rpm = std::round(speed * config_.prp_gr_rt * 30.0 / kPi);
    speed = rpm * kPi / 30.0 / config_.prp_gr_rt;
    const double wheel_count = 2.0 * kPi / (4.0 * config_.prp_enc_ppr * config_.prp_gr_rt);
    position = std::round(position / wheel_count) * wheel_count;
    if (config_.steered()) {
      const double steer_count = 2.0 * kPi / (4.0 * config_.str_enc_ppr * config_.str_gr_rt);
      steering = std::round(steering / steer_count) * steer_count;
    }
  }
  reading_.wheel_speed_radps = speed;
  reading_.wheel_position_rad = position;
  reading_.steering_rad = config_.steered() ? steering : 0.0;
  reading_.steering_speed_radps = steering_speed_;
  reading_.valid = true;
}

DriveFeedback SimulatedDrive::truth() const {
  DriveFeedback t;
  const double rolling_scale = 1.0 + options_.radius_error;
  t.wheel_speed_radps = wheel_speed_ * rolling_scale;
  t.wheel_position_rad = wheel_position_ * rolling_scale;
  t.steering_rad = steering_;
  t.steering_speed_radps = steering_speed_;
  t.valid = true;
  return t;
}

}  // namespace thorvald_base
