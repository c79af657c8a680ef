#include "thorvald_sim/physics_drive.h"

#include <algorithm>
#include <cmath>

namespace thorvald_sim {

thorvald_base::DriveFeedback encoderReading(const thorvald_base::DriveConfig& c, const JointMeasurement& m) {
  thorvald_base::DriveFeedback f;
  f.wheel_speed_radps = m.wheel_speed_radps;
  f.wheel_position_rad = m.wheel_position_rad;
  f.steering_rad = c.steered() ? m.steering_rad : 0.0;
  f.steering_speed_radps = c.steered() ? m.steering_speed_radps : 0.0;
  if (c.prp_gr_rt > 0.0) {
    const double rpm = std::round(m.wheel_speed_radps * c.prp_gr_rt * 30.0 / M_PI);
    f.wheel_speed_radps = rpm * M_PI / 30.0 / c.prp_gr_rt;
    if (c.prp_enc_ppr > 0.0) {
      const double count = 2.0 * M_PI / (4.0 * c.prp_enc_ppr * c.prp_gr_rt);
      f.wheel_position_rad = std::round(m.wheel_position_rad / count) * count;
    }
  }
  if (c.steered() && c.str_gr_rt > 0.0 && c.str_enc_ppr > 0.0) {
    const double count = 2.0 * M_PI / (4.0 * c.str_enc_ppr * c.str_gr_rt);
    f.steering_rad = std::round(m.steering_rad / count) * count;
  }
  f.valid = true;
  return f;
}

PhysicsDrive::PhysicsDrive(const thorvald_base::DriveConfig& config, double timeout_s)
    : config_(config), timeout_s_(timeout_s) {}

void PhysicsDrive::setCommand(const thorvald_base::DriveCommand& command) {
  command_ = command;
  if (!config_.steered()) command_.steering_rad = 0.0;
  if (config_.str_lim > 0.0)
    command_.steering_rad = std::clamp(command_.steering_rad, -config_.str_lim, config_.str_lim);
}

bool PhysicsDrive::measure(const JointMeasurement& m, double stamp_s) {
  if (!std::isfinite(m.wheel_position_rad) || !std::isfinite(m.wheel_speed_radps) || !std::isfinite(m.steering_rad) ||
      !std::isfinite(m.steering_speed_radps) || !std::isfinite(stamp_s))
    return false;
  reading_ = encoderReading(config_, m);
  last_measure_s_ = stamp_s;
  return true;
}

thorvald_base::DriveStatus PhysicsDrive::status() const {
  thorvald_base::DriveStatus s;
  // A simulation that was reset runs on with a later clock; a measurement "from the future" is not stale.
  s.online = last_measure_s_ >= 0.0 && now_s_ - last_measure_s_ <= timeout_s_;
  s.text = last_measure_s_ < 0.0 ? "no joint measurement from the simulator yet"
                                 : (s.online ? "ok" : "joint measurements from the simulator stopped");
  return s;
}

}  // namespace thorvald_sim
