#pragma once

#include <vector>

#include "cotton_harvester/control/rover_controller.h"
#include "cotton_harvester/control/simulated_controllers.h"

namespace cotton_harvester {
namespace control {

/// One sample of a closed-loop run.
struct StepSample {
  double t_s = 0.0;
  double position_m = 0.0;  ///< true position of the simulated rover
  double effort = 0.0;      ///< PID output u
  double pwm = 90.0;        ///< eq. 8 servo value sent
};

/// Figures of a position step response.
struct StepResponse {
  std::vector<StepSample> samples;
  double overshoot_m = 0.0;  ///< furthest travel past the target (0 when it never passes it)
  double settling_s = -1.0;  ///< time after which |error| stays within the band; -1: never settled
  double final_error_m = 0.0;
};

/// Runs the rover controller against the simulated navigation controller in simulated time, through
/// the same byte frames the serial port carries (telemetry in, drive commands out), for a step of
/// `step_m` from rest. The controller runs on each telemetry frame (every 20 ms).
StepResponse simulateStep(const RoverControllerParams& controller, const SimulatedNavigationParams& plant,
                          double step_m, double duration_s, double settle_band_m, double sim_dt_s = 0.002);

}  // namespace control
}  // namespace cotton_harvester
