#pragma once

// The cotton rover drives a whole field in MuJoCo, row after row: pure pursuit along each row's end waypoints (what a
// user records with the GNSS) and an omega turn on the headland into the next row, through the rover's own
// controller (RoverController: the deadband-aware speed control and the articulation P control through the two
// relays) talking to the simulated navigation controller (RoverSerialBridge) in its serial frames, on the fused pose
// (field_pose.h: wheel odometry, both IMUs and the RTK receiver through RoverFusion, as `odometry/filtered`; or the
// wheel odometry alone). The drive stops while the fusion's localization_ok is false and resumes when it is ok.
// The truth is read only to score: cross-track along the rows, the turns' entries, the driven path. ROS-free.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cotton_harvester/control/pure_pursuit.h"
#include "cotton_harvester/control/rover_controller.h"
#include "cotton_harvester/control/row_turn_planner.h"
#include "cotton_harvester_sim/rover_fusion.h"
#include "cotton_harvester_sim/rover_serial_bridge.h"
#include "cotton_harvester_sim/rover_sim.h"

namespace cotton_harvester {
namespace sim {

struct FieldRowsConfig {
  RoverSimParams sim;                     ///< the rover and the simulator's realism (`row` is the field's row)
  thorvald_sim::CottonFieldParams field;  ///< rows, spacing, length, plants
  control::RoverControllerParams rover;   ///< the rover node's controller
  SerialBridgeParams bridge;              ///< the simulated navigation controller
  control::PurePursuitParams pursuit;
  control::RowTurnParams turn;   ///< turn_radius_m >= minTurnRadius(articulation limit)
  double row_speed_mps = 0.25;   ///< harvest speed along the rows (RoverControllerParams::max_speed_mps)
  double turn_speed_mps = 0.15;  ///< on the headland
  /// The articulation moves at a fixed rate (the valve through two relays): while it lags its set-point by more than
  /// lag_slow_from_deg the rover slows, linearly down to lag_min_speed_fraction of its speed at lag_slow_full_deg, so
  /// the path it drives while the joint catches up is shorter (the omega's reversals, the turn's exit).
  double lag_slow_from_deg = 0.0;  ///< 0: never slows
  double lag_slow_full_deg = 10.0;
  double lag_min_speed_fraction = 0.4;
  double past_row_end_m = 0.5;       ///< a row's leg ends this far past its last plant [m]
  double start_before_row_m = 1.5;   ///< the front axle starts this far before the first row's first plant [m]
  double control_period_s = 0.02;    ///< the navigation controller's telemetry period [s]
  double entry_tolerance_m = 0.10;   ///< a turn succeeds when the rover enters the next row within this ...
  double entry_tolerance_deg = 5.0;  ///< ... and this of its line
  double time_limit_s = 1800.0;      ///< simulated [s]
  std::string waypoints_path;        ///< when set: the rows' end waypoints are written there (YAML)
  /// When set: one CSV line per control step there (the truth's and the estimate's front axle, the articulation
  /// asked, measured and true, pure pursuit's curvature, cross-track and progress) for finding where a turn goes wrong.
  std::string trace_path;
  /// The pose pure pursuit follows: true the fusion's (odometry, two IMUs, RTK GNSS) in the rows' GNSS frame, false
  /// the wheel odometry from the surveyed start.
  bool fused_pose = true;
  RoverFusionParams fusion;  ///< the fusion's inputs and timeouts (kinematics and encoders: the simulation's)
  /// The localisation sensors' realism when it differs from the world's (sim.realism); empty: the world's.
  std::optional<thorvald_sim::Realism> sensor_realism;
  double resume_after_s = 0.5;  ///< the drive resumes once the fusion has been ok this long [s]
  /// Called on every leg's start and end with a progress line.
  std::function<void(const std::string&)> progress;
};

/// One row as driven: cross-track of the true front axle against the row's line between its first and last plant.
struct FieldRowReport {
  int row = 0;
  bool completed = false;          ///< the rover drove past the last plant with the camera over the row
  double cross_track_rms_m = 0.0;  ///< truth [m]
  double cross_track_max_m = 0.0;  ///< truth [m]
  double odometry_error_m = 0.0;   ///< the pose the rover used minus the truth at the row's end [m]
  double time_s = 0.0;             ///< on the row's leg [s]
  int bolls = 0;
};

/// One headland turn, scored where the rover enters the next row (its first plant).
struct FieldTurnReport {
  int from_row = 0;
  bool success = false;
  double entry_cross_track_m = 0.0;  ///< truth [m]
  double entry_heading_deg = 0.0;    ///< truth [deg]
  double depth_m = 0.0;              ///< how far past the row's last plant the rover went (truth) [m]
  double planned_depth_m = 0.0;      ///< how far past the row's last plant the plan goes [m]
};

struct FieldRowsReport {
  std::vector<FieldRowReport> rows;
  std::vector<FieldTurnReport> turns;
  thorvald_sim::CottonFieldTruth field;
  std::vector<Eigen::Vector2d> truth_path;     ///< the true front axle, every 0.2 s [m]
  std::vector<Eigen::Vector2d> estimate_path;  ///< the pose the rover drove on [m]
  std::vector<Eigen::Vector2d> planned_path;   ///< all legs' waypoints [m]
  std::vector<BollTruth> bolls;                ///< at the end
  double cross_track_rms_m = 0.0;              ///< over all rows [m]
  double rows_completed_pct = 0.0;
  double turn_success_pct = 0.0;
  double sim_time_s = 0.0, wall_time_s = 0.0;
  int stops = 0;           ///< times the drive stopped on the fusion's localization_ok (the wait for the datum too)
  double stopped_s = 0.0;  ///< simulated time stopped [s]
  std::string error;       ///< set when the run could not be done
};

/// Drives the field. Never throws; `error` says what went wrong.
FieldRowsReport runFieldRows(const FieldRowsConfig& config);

/// A top view of the field: rows' plants, bolls (picked green, missed red), the planned legs, the true path (blue)
/// and the pose the rover drove on (orange), as PNG. False when it cannot be written.
bool writeFieldPng(const FieldRowsReport& report, const std::string& path);

/// The field of the goals: `rows` rows of `length_m` 91.44 cm apart on flat ground, ideal plants.
FieldRowsConfig fieldRowsConfig(int rows, double length_m, unsigned seed);

}  // namespace sim
}  // namespace cotton_harvester
