#pragma once

// The paper's Table 1 in MuJoCo: the rover drives a closed loop on the field-like ground (the field test's
// 2.77 deg slope, no plants in the way) with scripted commands -- straight, a U-turn on a fixed articulation, straight
// back, a U-turn, straight to the start -- while its sensors (rover_sensors.h) feed one filter per sensor set
// (rover_fusion.h). The loop-closure error of a set is the distance between its estimate and the true base_link
// at the end (both relative to the start), the standard deviation the filter's own sigma of x and y there. An
// optional GNSS outage (a tree line) measures how far the estimate drifts while the fix is gone and how far it
// steps when the fix returns. ROS-free, headless.

#include <optional>
#include <string>
#include <vector>

#include "cotton_harvester_sim/rover_fusion.h"
#include "cotton_harvester_sim/rover_sensors.h"
#include "cotton_harvester_sim/rover_sim.h"

namespace cotton_harvester {
namespace sim {

struct FieldLoopConfig {
  thorvald_sim::Realism realism = thorvald_sim::Realism::kIdeal;
  unsigned seed = 1;
  double slope_deg = 2.7668;     ///< the field test's slope (Table 3)
  double straight_m = 20.0;      ///< each of the two long legs [m]
  double turn_deg = 30.0;        ///< articulation of the U-turns [deg]
  double pwm = 115.0;            ///< swashplate PWM while driving (about 0.39 m/s)
  double wait_for_fix_s = 20.0;  ///< standing still at the start until the receiver is fixed [s]
  /// GNSS outage: no fix from this long after the start of the drive, for outage_s [s]; 0: none.
  double outage_start_s = 0.0, outage_s = 0.0;
  std::vector<SensorSet> sets = {kTable1Sets.begin(), kTable1Sets.end()};
  RoverFusionParams fusion;
  /// The encoders' metres per pulse measured first with the RTK receiver on a straight drive (as the rover's owner
  /// calibrates them); false: the nominal 1.8 mm.
  bool calibrate_odometry = true;
  double time_limit_s = 600.0;  ///< of driving [s]
};

struct Table1Row {
  SensorSet set = SensorSet::kOdometry;
  double error_x_m = 0.0, error_y_m = 0.0, error_m = 0.0;  ///< |estimate - truth| at the loop's end [m]
  double sigma_x_m = 0.0, sigma_y_m = 0.0;                 ///< the estimate's 1-sigma there [m]
  bool localization_ok = true;                             ///< at the end
};

struct OutageFigures {
  double drift_m = 0.0;        ///< largest |estimate - truth| from the outage's start to the first fix after it [m]
  double return_step_m = 0.0;  ///< largest position step of one GNSS update within 30 s of the fix's return [m]
  double fixed_return_step_m = 0.0;  ///< the step at the first RTK-fixed epoch after the outage [m]
  double error_before_m = 0.0;       ///< |estimate - truth| when the outage began [m]
  bool ok_through_outage = true;     ///< localization_ok stayed true through the outage
  double fix_gone_s = 0.0;           ///< how long no fix was fused [s]
};

struct FieldLoopResult {
  std::vector<Table1Row> rows;
  std::optional<OutageFigures> outage;  ///< for the first set with a GNSS
  double loop_length_m = 0.0;           ///< true path length of base_link [m]
  double metres_per_pulse = 0.0;        ///< what the filters used [m]
  double encoder_travel_m = 0.0;        ///< the front encoders' mean count times metres_per_pulse [m]
  double closure_gap_m = 0.0;           ///< true distance between the end and the start [m]
  double drive_s = 0.0, wall_s = 0.0;
};

/// Runs the loop. Throws what RoverSim and RoverSensors throw on bad parameters, std::runtime_error when the loop
/// does not end within time_limit_s.
FieldLoopResult runFieldLoop(const FieldLoopConfig& config);

}  // namespace sim
}  // namespace cotton_harvester
