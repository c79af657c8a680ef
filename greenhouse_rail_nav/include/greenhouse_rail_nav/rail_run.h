#pragma once

#include <string>
#include <vector>

#include "thorvald_base/pose2d.h"

namespace greenhouse_rail_nav {

/// Distance [m] to what lies straight ahead in a planar scan: the median of the finite returns within
/// ±half_width_rad of the scan's x axis. NaN when there is none (nothing seen ahead, or a bad scan).
double forwardRange(const std::vector<float>& ranges, double angle_min_rad, double angle_increment_rad,
                    double half_width_rad, double range_min_m, double range_max_m);

/// The drive along one rail set (greenhouse paper §V-A3): forward at the treatment speed until the lidar's
/// distance to the far wall says the end of the rail is reached, then back, slowing down after
/// `slow_fraction` of the driven length until the range finders sense the floor. With the set's length known (the
/// rail-set file's `length:`) the robot drives on until the lamps have lit the row to its end (as far as the drive
/// wheels may go on the pipes), the far wall a guard only.
struct RailRunParams {
  double treat_speed_mps = 0.5;      ///< the paper's UV dose needs 0.5 m/s [m/s]
  double accel_mps2 = 0.5;           ///< [m/s^2]
  double end_wall_range_m = 1.3;     ///< stop when the far wall is this close to the lidar [m]
  double return_speed_mps = 0.5;     ///< [m/s]
  double slow_fraction = 0.9;        ///< slow down after this fraction of the driven length on the way back
  double slow_speed_mps = 0.12;      ///< [m/s]
  double max_rail_length_m = 150.0;  ///< a run longer than this is stopped as an error [m]
  /// Length known: the drive axle stops at least this far before the rails' far end, where the drive rail wheels
  /// still stand on the pipes (the lamps' front edge then 3 cm short of it with the placeholder lamps) [m].
  double rail_end_margin_m = 0.08;
  /// Length known: the far wall's guard; stop wherever the lidar sees the far wall this close, whatever odometry says
  /// (the lidar 0.45 m ahead of the axle, the frame's front range finders 0.52 m: 0.53 m clear of the wall) [m].
  double wall_guard_range_m = 0.6;
  /// The lamps' lit stretch along the row: `lamp_length_m` centred `lamp_offset_m` along base_link's x
  /// (config/uv_lamps.yaml, the one lamp geometry of uv_dose, the mission and the bench's scorer) [m].
  double lamp_length_m = 0.75;
  double lamp_offset_m = -0.325;
  /// The way back is watched with odometry alone (what else there is on the rails): it stops with a reason when the
  /// robot has backed, by odometry, `return_overrun_m` plus `return_overrun_fraction` of the driven length more than
  /// it drove in, ...
  double return_overrun_m = 1.0;
  double return_overrun_fraction = 0.1;
  /// ... when it has come no nearer the headland for `return_stall_s` while driving (the wheels turn but odometry's
  /// heading points elsewhere, or the drives do not move the robot) [s], ...
  double return_stall_s = 5.0;
  /// ... or when, off the rails (no pipe to guide it), its heading is more than this off the heading it entered with
  /// [rad]: backing on would swing the frame through the headland, not along the rails' line.
  double return_max_heading_error_rad = 0.5;

  std::string validate() const;
};

/// Speed [m/s] (>= 0, the caller sets the sign) on the way in: ramps up to the treatment speed, and brakes
/// so that it stops when the far wall reaches end_wall_range_m. `wall_range_m` may be NaN (no wall seen yet).
double inboundSpeed(const RailRunParams& p, double current_speed_mps, double wall_range_m, double dt_s);

/// Where base_link stops along a row of known length, from the row's start [m]: where the lamps' lit stretch has
/// passed the row's end, but no nearer the rails' end than rail_end_margin.
double rowStopPosition(const RailRunParams& p, double row_length_m);

/// Speed [m/s] (>= 0) on the way in along a row of known length with base_link at `row_position_m` from its start:
/// ramps up to the treatment speed and brakes to stop at rowStopPosition, or earlier where the far wall comes within
/// wall_guard_range of the lidar (`wall_range_m` NaN: not seen).
double inboundSpeedToRowEnd(const RailRunParams& p, double current_speed_mps, double row_position_m,
                            double row_length_m, double wall_range_m, double dt_s);

/// Which share of a row of known length the lamps' lit stretch passed over with the lights on, in bins of `bin_m`:
/// base_link's motion along the row is reported tick by tick with the lights' state.
class RowLitCoverage {
 public:
  RowLitCoverage() = default;
  RowLitCoverage(const RailRunParams& p, double row_length_m, double bin_m = 0.05);
  /// base_link moved from `from_m` to `to_m` along the row (from its start) [m] with the lights `on`.
  void add(double from_m, double to_m, bool on);
  /// Share of [0, row length] lit, in [0, 1] (1 for an empty row).
  double fraction() const;
  double rowLength() const { return row_length_m_; }

 private:
  double rear_m_ = 0.0, front_m_ = 0.0, row_length_m_ = 0.0, bin_m_ = 0.05;
  std::vector<bool> lit_;
};

/// Speed magnitude [m/s] on the way back after `reversed_m` of `driven_in_m`.
double returnSpeed(const RailRunParams& p, double current_speed_mps, double reversed_m, double driven_in_m,
                   double dt_s);

/// Watches the way back from the rails to the pose stored before entering them, with what odometry alone tells (the
/// lidar sees only the row's end on the rails): the path odometry has backed, the progress towards the stored pose,
/// and the heading once off the rails. A return that drives on while one of them is wrong swings the robot through the
/// headland or pushes it against what stops it, wheels turning, for as long as nothing stops it.
class ReturnWatch {
 public:
  /// `entry`: the odometry pose stored before entering, `driven_in_m` along its heading; `now_s` the start.
  ReturnWatch(const RailRunParams& p, const thorvald_base::Pose2D& entry, double driven_in_m, double now_s);
  /// One control tick: the odometry pose, whether the wheels read rail, whether the robot is being driven back (a
  /// hold for a person does not count towards a stall). Returns why the return must stop, empty while all is well.
  std::string update(const thorvald_base::Pose2D& odom, bool on_rails, bool driving, double now_s);
  double backedM() const { return backed_m_; }  ///< odometry's path length so far [m]

 private:
  RailRunParams p_;
  thorvald_base::Pose2D entry_, last_;
  double driven_in_m_;
  double backed_m_ = 0.0;
  double best_along_;     ///< the nearest odometry came to the stored pose along its heading [m]
  double progress_at_s_;  ///< when it last came nearer (or the robot last stood still for a hold)
  bool started_ = false;
};

/// The speed held at cruise while treating, as the report gives it: odometry comes at its own rate, so over one
/// control tick the pose may not have moved at all, or moved twice; the speed is measured over windows of at least
/// window_s instead, and their mean and standard deviation reported. A tick off cruise (ramping, braking, a
/// safety stop) or without elapsed time drops the open window.
class CruiseSpeedMeter {
 public:
  explicit CruiseSpeedMeter(double window_s = 0.5) : window_s_(window_s) {}
  /// One control tick: `moved_m` [m] driven over `dt_s` [s], `cruising` when the commanded speed was the cruise
  /// speed.
  void add(bool cruising, double moved_m, double dt_s);
  int windows() const { return n_; }  ///< closed windows
  /// Mean and standard deviation of the windows' speeds [m/s]; false (outputs untouched) without a closed window.
  bool stats(double* mean_mps, double* std_mps) const;

 private:
  double window_s_;
  double open_m_ = 0.0, open_s_ = 0.0;
  double sum_ = 0.0, sum2_ = 0.0;
  int n_ = 0;
};

}  // namespace greenhouse_rail_nav
