#include "cotton_harvester/control/simulated_controllers.h"

#include <algorithm>
#include <cmath>

namespace cotton_harvester {
namespace control {

SimulatedManipulationController::SimulatedManipulationController(const SimulatedManipulatorParams& params)
    : params_(params),
      horizontal_(params.horizontal_min_steps, params.horizontal_max_steps, params.horizontal_steps_per_s,
                  params.horizontal_start_steps),
      vertical_(params.vertical_min_steps, params.vertical_max_steps, params.vertical_steps_per_s,
                params.vertical_start_steps) {}

void SimulatedManipulationController::appendReport(std::vector<std::uint8_t>* out, Axis axis) const {
  const StepperAxisModel& model = axis == Axis::kHorizontal ? horizontal_ : vertical_;
  ManipulatorReport report;
  report.target =
      axis == Axis::kHorizontal ? ManipulatorReport::Target::kHorizontal : ManipulatorReport::Target::kVertical;
  report.position_steps = static_cast<std::int16_t>(model.positionSteps());
  report.moving = model.moving();
  report.limit = model.limitHit();
  const auto frame = encodeReport(report);
  out->insert(out->end(), frame.begin(), frame.end());
}

std::vector<std::uint8_t> SimulatedManipulationController::receive(const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint8_t> out;
  for (const auto& frame : parser_.push(data, size)) {
    ManipulatorCommand command;
    if (!decodeCommand(frame, &command)) continue;
    ++commands_;
    switch (command.kind) {
      case ManipulatorCommand::Kind::kMove:
        (command.move.axis == Axis::kHorizontal ? horizontal_ : vertical_)
            .start(command.move.positive, command.move.steps);
        if (command.move.steps == 0) appendReport(&out, command.move.axis);
        break;
      case ManipulatorCommand::Kind::kBrush: {
        brush_on_ = command.brush_on;
        ManipulatorReport report;
        report.target = ManipulatorReport::Target::kBrush;
        report.brush_on = brush_on_;
        const auto reply = encodeReport(report);
        out.insert(out.end(), reply.begin(), reply.end());
        break;
      }
      case ManipulatorCommand::Kind::kStop:
        horizontal_.stop();
        vertical_.stop();
        brush_on_ = false;
        appendReport(&out, Axis::kHorizontal);
        appendReport(&out, Axis::kVertical);
        break;
      case ManipulatorCommand::Kind::kQuery:
        appendReport(&out, Axis::kHorizontal);
        appendReport(&out, Axis::kVertical);
        break;
    }
  }
  return out;
}

std::vector<std::uint8_t> SimulatedManipulationController::step(double dt_s) {
  std::vector<std::uint8_t> out;
  const bool was_moving = horizontal_.moving() || vertical_.moving();
  if (horizontal_.step(dt_s)) appendReport(&out, Axis::kHorizontal);
  if (vertical_.step(dt_s)) appendReport(&out, Axis::kVertical);
  since_report_s_ += dt_s;
  if (was_moving && since_report_s_ >= params_.report_period_s) {
    since_report_s_ = 0.0;
    if (horizontal_.moving()) appendReport(&out, Axis::kHorizontal);
    if (vertical_.moving()) appendReport(&out, Axis::kVertical);
  }
  return out;
}

SimulatedNavigationController::SimulatedNavigationController(const SimulatedNavigationParams& params)
    : params_(params), drive_(params.drive), rng_(params.seed) {}

void SimulatedNavigationController::receive(const std::uint8_t* data, std::size_t size) {
  parser_.push(data, size);
  for (const auto& command : parser_.takeCommands()) {
    ++commands_;
    clamped_ = command.pwm < params_.drive.pwm_min || command.pwm > params_.drive.pwm_max;
    pwm_ = std::clamp<double>(command.pwm, params_.drive.pwm_min, params_.drive.pwm_max);
    left_ = command.relay_left;
    right_ = command.relay_right;
    if (left_ && right_) left_ = right_ = false;  // the valve cannot go both ways
    since_command_s_ = 0.0;
    watchdog_stop_ = false;
  }
}

std::vector<std::uint8_t> SimulatedNavigationController::step(double dt_s) {
  std::vector<std::uint8_t> out;
  if (!(dt_s > 0.0)) return out;
  since_command_s_ += dt_s;
  if (since_command_s_ > params_.watchdog_s) {
    watchdog_stop_ = true;
    pwm_ = params_.drive.neutral_pwm;
    left_ = right_ = false;
  }
  drive_.step(pwm_, left_, right_, dt_s);
  since_telemetry_s_ += dt_s;
  if (since_telemetry_s_ + 1e-9 >= params_.telemetry_period_s) {
    since_telemetry_s_ = 0.0;
    std::uniform_real_distribution<double> noise(-params_.pot_noise_counts, params_.pot_noise_counts);
    const double pot = params_.pot_center_counts + params_.pot_counts_per_deg * drive_.articulationDeg() + noise(rng_);
    Telemetry telemetry;
    telemetry.encoder_count = drive_.encoderCount();
    telemetry.pot_counts = static_cast<std::uint16_t>(std::clamp(std::lround(pot), 0L, 1023L));
    telemetry.watchdog_stop = watchdog_stop_;
    telemetry.pwm_clamped = clamped_;
    const auto frame = encodeTelemetry(telemetry);
    out.insert(out.end(), frame.begin(), frame.end());
  }
  return out;
}

}  // namespace control
}  // namespace cotton_harvester
