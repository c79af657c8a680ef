#include "cotton_harvester_sim/rover_serial_bridge.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace cotton_harvester {
namespace sim {

namespace {
bool positive(double v) { return v > 0.0 && std::isfinite(v); }
}  // namespace

std::string SerialBridgeParams::check() const {
  if (auto bad = calibration.check(); !bad.empty()) return "calibration/" + bad;
  const std::pair<const char*, double> values[] = {{"vertical_steps_per_s", vertical_steps_per_s},
                                                   {"horizontal_steps_per_s", horizontal_steps_per_s},
                                                   {"report_period_s", report_period_s},
                                                   {"pot_counts_per_deg", pot_counts_per_deg},
                                                   {"telemetry_period_s", telemetry_period_s},
                                                   {"watchdog_s", watchdog_s},
                                                   {"articulation_rate_deg_s", articulation_rate_deg_s}};
  for (const auto& [key, v] : values)
    if (!positive(v)) return std::string(key) + ": expected > 0";
  if (!(pot_noise_counts >= 0.0) || !std::isfinite(pot_noise_counts)) return "pot_noise_counts: expected >= 0";
  if (!(pot_center_counts >= 0.0 && pot_center_counts <= 1023.0)) return "pot_center_counts: expected 0..1023";
  return "";
}

control::ManipulatorCalibration simArmCalibration(const RoverGeometry& geometry) {
  control::ManipulatorCalibration c;
  c.vertical_min_distance_m = geometry.min_depth_m;
  c.vertical_max_distance_m = geometry.max_depth_m;
  c.horizontal_min_m = 0.0;
  c.horizontal_max_m = geometry.horizontal_travel_m;
  return c;
}

namespace {

control::SimulatedManipulatorParams manipulatorParams(const SerialBridgeParams& p, const RoverSim& sim) {
  if (auto bad = p.check(); !bad.empty()) throw std::invalid_argument("serial bridge: " + bad);
  const control::ManipulatorCalibration& c = p.calibration;
  control::SimulatedManipulatorParams m;
  const double v_a = c.verticalStepsFromDistance(c.vertical_min_distance_m);
  const double v_b = c.verticalStepsFromDistance(c.vertical_max_distance_m);
  m.vertical_min_steps = static_cast<std::int32_t>(std::ceil(std::min(v_a, v_b)));
  m.vertical_max_steps = static_cast<std::int32_t>(std::floor(std::max(v_a, v_b)));
  m.horizontal_min_steps = static_cast<std::int32_t>(std::ceil(c.horizontalStepsFromExtension(c.horizontal_min_m)));
  m.horizontal_max_steps = static_cast<std::int32_t>(std::floor(c.horizontalStepsFromExtension(c.horizontal_max_m)));
  if (m.vertical_min_steps < -32768 || m.vertical_max_steps > 32767 || m.horizontal_max_steps > 32767)
    throw std::invalid_argument("serial bridge: calibration: step positions beyond the reports' int16");
  m.vertical_steps_per_s = p.vertical_steps_per_s;
  m.horizontal_steps_per_s = p.horizontal_steps_per_s;
  m.report_period_s = p.report_period_s;
  // The counters start where the simulated arm is (a real controller is homed before the run).
  m.vertical_start_steps = std::clamp<std::int32_t>(
      static_cast<std::int32_t>(std::lround(c.verticalStepsFromDistance(sim.verticalPosition()))), m.vertical_min_steps,
      m.vertical_max_steps);
  m.horizontal_start_steps = std::clamp<std::int32_t>(
      static_cast<std::int32_t>(std::lround(c.horizontalStepsFromExtension(sim.horizontalPosition()))),
      m.horizontal_min_steps, m.horizontal_max_steps);
  return m;
}

}  // namespace

RoverSerialBridge::RoverSerialBridge(RoverSim& sim, const SerialBridgeParams& params)
    : sim_(sim), params_(params), manipulator_(manipulatorParams(params, sim)), rng_(params.seed) {
  articulation_deg_ = sim_.potentiometerDeg();
}

std::vector<std::uint8_t> RoverSerialBridge::receiveManipulator(const std::uint8_t* data, std::size_t size) {
  return manipulator_.receive(data, size);
}

void RoverSerialBridge::receiveNavigation(const std::uint8_t* data, std::size_t size) {
  parser_.push(data, size);
  const double pwm_min = sim_.params().drive.pwm_min, pwm_max = sim_.params().drive.pwm_max;
  for (const auto& command : parser_.takeCommands()) {
    ++drive_commands_;
    clamped_ = command.pwm < pwm_min || command.pwm > pwm_max;
    pwm_ = std::clamp<double>(command.pwm, pwm_min, pwm_max);
    left_ = command.relay_left;
    right_ = command.relay_right;
    if (left_ && right_) left_ = right_ = false;  // the valve cannot go both ways
    since_command_s_ = 0.0;
    watchdog_stop_ = false;
  }
}

RoverSerialBridge::Output RoverSerialBridge::advance(double dt_s) {
  Output out;
  if (!(dt_s > 0.0) || !std::isfinite(dt_s)) return out;
  since_command_s_ += dt_s;
  if (since_command_s_ > params_.watchdog_s) {
    watchdog_stop_ = true;
    pwm_ = sim_.params().drive.neutral_pwm;
    left_ = right_ = false;
  }
  // Steppers: the controller's counters; the simulated axes follow them at the same rates.
  out.manipulator = manipulator_.step(dt_s);
  const control::ManipulatorCalibration& c = params_.calibration;
  sim_.commandHorizontal(c.horizontalExtensionFromSteps(manipulator_.horizontal().positionSteps()));
  sim_.commandVertical(c.verticalDistanceFromSteps(manipulator_.vertical().positionSteps()));
  sim_.setVacuum(manipulator_.brushOn());
  // Drive and articulation valve.
  sim_.setSwashplatePwm(pwm_);
  const double limit = sim_.params().geometry.articulation_limit_deg;
  const double turn = params_.articulation_rate_deg_s * dt_s * ((left_ ? 1.0 : 0.0) - (right_ ? 1.0 : 0.0));
  articulation_deg_ = std::clamp(articulation_deg_ + turn, -limit, limit);
  sim_.setArticulationDeg(articulation_deg_);
  sim_.advance(dt_s);

  since_telemetry_s_ += dt_s;
  if (since_telemetry_s_ + 1e-9 >= params_.telemetry_period_s) {
    since_telemetry_s_ = 0.0;
    std::uniform_real_distribution<double> noise(-params_.pot_noise_counts, params_.pot_noise_counts);
    const double pot = params_.pot_center_counts + params_.pot_counts_per_deg * sim_.potentiometerDeg() + noise(rng_);
    control::Telemetry telemetry;
    telemetry.encoder_count = sim_.encoderCount();
    telemetry.pot_counts = static_cast<std::uint16_t>(std::clamp(std::lround(pot), 0L, 1023L));
    telemetry.watchdog_stop = watchdog_stop_;
    telemetry.pwm_clamped = clamped_;
    out.navigation = control::encodeTelemetry(telemetry);
  }
  return out;
}

}  // namespace sim
}  // namespace cotton_harvester
