#include "cotton_harvester/control/step_response.h"

#include <cmath>

#include "cotton_harvester/control/navigation_protocol.h"

namespace cotton_harvester {
namespace control {

StepResponse simulateStep(const RoverControllerParams& controller_params, const SimulatedNavigationParams& plant,
                          double step_m, double duration_s, double settle_band_m, double sim_dt_s) {
  SimulatedNavigationController navigation(plant);
  RoverController controller(controller_params);
  NavigationFrameParser host_parser;
  StepResponse response;
  bool target_set = false;
  std::uint8_t sequence = 0;
  double last_control_t = 0.0;
  double last_outside_t = 0.0;
  double effort = 0.0, pwm = 90.0;
  const int steps = static_cast<int>(std::ceil(duration_s / sim_dt_s));
  for (int i = 1; i <= steps; ++i) {
    const double t = i * sim_dt_s;
    const auto bytes = navigation.step(sim_dt_s);
    host_parser.push(bytes.data(), bytes.size());
    for (const auto& telemetry : host_parser.takeTelemetry()) {
      const double dt = target_set ? t - last_control_t : plant.telemetry_period_s;
      if (!target_set) {
        controller.update(telemetry, dt);  // first frame: learn where the rover is
        controller.setPositionTarget(controller.positionM() + step_m);
        target_set = true;
      }
      const RoverOutput output = controller.update(telemetry, dt);
      last_control_t = t;
      effort = output.effort;
      pwm = output.pwm;
      DriveCommand command = output.command();
      command.sequence = sequence++;
      const auto frame = encodeDriveCommand(command);
      navigation.receive(frame.data(), frame.size());
    }
    const double position = navigation.drive().positionM();
    response.samples.push_back(StepSample{t, position, effort, pwm});
    const double past = step_m >= 0.0 ? position - step_m : step_m - position;
    if (past > response.overshoot_m) response.overshoot_m = past;
    if (std::abs(position - step_m) > settle_band_m) last_outside_t = t;
  }
  const double final_position = navigation.drive().positionM();
  response.final_error_m = final_position - step_m;
  response.settling_s =
      std::abs(response.final_error_m) <= settle_band_m && last_outside_t < duration_s - 1.0 ? last_outside_t : -1.0;
  return response;
}

}  // namespace control
}  // namespace cotton_harvester
