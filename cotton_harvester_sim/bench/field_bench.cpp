// field_bench: the cotton rover in a field, headless in MuJoCo. One mode per experiment:
//   --mode table1  the paper's Table 1: a closed loop (20 m legs, two U-turns) on the field-like slope, the
//                  loop-closure error and the estimate's standard deviation of the five sensor sets;
//   --mode outage  the same loop with a 30 s GNSS outage (a tree line) bridged by the IMUs and the odometry;
//   --mode rows    the rover follows the rows of a field and turns at their ends (field_rows.h: pure pursuit on the
//                  fused pose or, --pose odometry, on the wheel odometry; the truth only scores).
// Prints a table and one line
//   RESULT {"realism": .., "loop_closure_err_m": .., "<set>_err_m": .., "<set>_sigma_m": .., ...}
// (table1: loop_closure_err_m is odometry + two IMUs + one GNSS's; outage: outage_drift_m, outage_return_step_m,
// fix_return_step_m; rows: cross_track_rms_m, row_end_turn_success_pct, rows_completed_pct, ...).
//   field_bench --mode rows                    (4 rows x 20 m, the field)
//   field_bench --mode rows --rows 2 --length 4 --png /tmp/field.png --waypoints /tmp/field_rows.yaml
#include <cmath>
#include <cstdio>
#include <string>

#include <CLI/CLI.hpp>
#include <thorvald_common/command_line.h>

#include "cotton_harvester_sim/field_loop.h"
#include "cotton_harvester_sim/field_rows.h"

namespace {

using cotton_harvester::sim::FieldLoopConfig;
using cotton_harvester::sim::FieldLoopResult;
using cotton_harvester::sim::SensorSet;

void printRows(const FieldLoopResult& r) {
  std::printf("%-34s %22s %22s %5s\n", "sensor set", "loop closure err x,y", "estimate std dev x,y", "ok");
  for (const auto& row : r.rows)
    std::printf("%-34s %10.2f,%-11.2f %10.2f,%-11.2f %5s\n", cotton_harvester::sim::sensorSetName(row.set),
                row.error_x_m, row.error_y_m, row.sigma_x_m, row.sigma_y_m, row.localization_ok ? "yes" : "no");
  std::printf(
      "loop: %.1f m driven (encoders: %.1f m at %.3f mm per pulse) in %.1f s (simulated), true end %.3f m from the "
      "start; %.1f s "
      "wall\n",
      r.loop_length_m, r.encoder_travel_m, 1e3 * r.metres_per_pulse, r.drive_s, r.closure_gap_m, r.wall_s);
}

std::string rowKeys(const FieldLoopResult& r) {
  std::string keys;
  char buf[160];
  for (const auto& row : r.rows) {
    const char* k = cotton_harvester::sim::sensorSetKey(row.set);
    std::snprintf(buf, sizeof buf, ", \"%s_err_m\": %.3f, \"%s_sigma_m\": %.3f", k, row.error_m, k,
                  std::hypot(row.sigma_x_m, row.sigma_y_m));
    keys += buf;
  }
  return keys;
}

struct RowsOptions {
  int rows = 4;
  double length = 20.0, speed = 0.25;
  double heading_correction_gain = -1.0;  ///< < 0: fieldRowsConfig's
  double lag_slow_from_deg = -1.0;        ///< < 0: fieldRowsConfig's
  std::string pose = "fused", png, waypoints, world, trace;
};

int runRows(const RowsOptions& o, const std::string& realism_name, unsigned seed) {
  cotton_harvester::sim::FieldRowsConfig c = cotton_harvester::sim::fieldRowsConfig(o.rows, o.length, seed);
  c.sim.realism = *thorvald_sim::realismFromName(o.world.empty() ? realism_name : o.world);
  c.sensor_realism = thorvald_sim::realismFromName(realism_name);
  c.fused_pose = o.pose == "fused";
  c.row_speed_mps = o.speed;
  c.rover.max_speed_mps = std::max(c.rover.max_speed_mps, o.speed);
  c.waypoints_path = o.waypoints;
  c.trace_path = o.trace;
  if (o.heading_correction_gain >= 0.0) c.pursuit.heading_correction_gain = o.heading_correction_gain;
  if (o.lag_slow_from_deg >= 0.0) c.lag_slow_from_deg = o.lag_slow_from_deg;
  c.time_limit_s = 600.0 + o.rows * (o.length / o.speed + 120.0);
  c.progress = [](const std::string& line) { std::printf("%s\n", line.c_str()); };
  const cotton_harvester::sim::FieldRowsReport r = cotton_harvester::sim::runFieldRows(c);
  for (const auto& row : r.rows)
    std::printf("row %d: %s, cross-track rms %.3f m, max %.3f m, pose off by %.3f m at its end, %.0f s\n", row.row,
                row.completed ? "completed" : "NOT completed", row.cross_track_rms_m, row.cross_track_max_m,
                row.odometry_error_m, row.time_s);
  for (const auto& t : r.turns)
    std::printf("turn after row %d: %s, entry %.3f m / %.1f deg, %.2f m deep (planned %.2f)\n", t.from_row,
                t.success ? "entered" : "FAILED", t.entry_cross_track_m, t.entry_heading_deg, t.depth_m,
                t.planned_depth_m);
  std::printf("pose: %s; stopped %d times on localization_ok, %.1f s in all\n", o.pose.c_str(), r.stops, r.stopped_s);
  if (!r.error.empty()) std::printf("error: %s\n", r.error.c_str());
  if (!o.png.empty() && !cotton_harvester::sim::writeFieldPng(r, o.png))
    std::printf("could not write %s\n", o.png.c_str());
  std::printf(
      "RESULT {\"realism\": \"%s\", \"world_realism\": \"%s\", \"pose\": \"%s\", \"rows\": %d, \"row_length_m\": %.1f, "
      "\"speed_mps\": %.2f, "
      "\"cross_track_rms_m\": %.4f, \"row_end_turn_success_pct\": %.1f, \"rows_completed_pct\": %.1f, \"stops\": %d, "
      "\"sim_s\": %.1f, \"wall_s\": %.1f}\n",
      realism_name.c_str(), (o.world.empty() ? realism_name : o.world).c_str(), o.pose.c_str(), o.rows, o.length,
      o.speed, r.cross_track_rms_m, r.turn_success_pct, r.rows_completed_pct, r.stops, r.sim_time_s, r.wall_time_s);
  return r.error.empty() ? 0 : 1;
}

double errorOf(const FieldLoopResult& r, SensorSet set) {
  for (const auto& row : r.rows)
    if (row.set == set) return row.error_m;
  return -1.0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"field_bench: the cotton rover's localisation in a field (MuJoCo)"};
  std::string mode = "table1", realism_name = "ideal";
  FieldLoopConfig c;
  double outage_s = 30.0;
  bool no_calibration = false;
  double outage_start_s = 10.0;
  RowsOptions rows;
  app.add_option("--mode", mode,
                 "table1 (the five sensor sets), outage (a GNSS outage on the loop) or rows (a field's rows followed)")
      ->check(CLI::IsMember({"table1", "outage", "rows"}));
  app.add_option("--realism", realism_name, "the sensors: ideal (no errors) or datasheet")
      ->check(CLI::IsMember({"ideal", "datasheet"}));
  app.add_option("--seed", c.seed, "the sensors' errors and the receiver's");
  app.add_option("--straight", c.straight_m, "length of each long leg [m]")->check(CLI::Range(2.0, 100.0));
  app.add_flag("--no-calibration", no_calibration, "the encoders' nominal 1.8 mm per pulse, not a calibrated one");
  app.add_option("--outage", outage_s, "outage mode: the outage's length [s]")->check(CLI::Range(1.0, 300.0));
  app.add_option("--outage-start", outage_start_s,
                 "outage mode: when it begins after the drive's start [s] (10: on the first leg, a tree line along "
                 "the row; 45: it runs into the first U-turn)")
      ->check(CLI::Range(0.0, 300.0));
  app.add_option("--rows", rows.rows, "rows mode: rows in the field")->check(CLI::Range(1, 40));
  app.add_option("--length", rows.length, "rows mode: row length [m]")->check(CLI::Range(0.5, 200.0));
  app.add_option("--speed", rows.speed, "rows mode: harvest speed along the rows [m/s]")->check(CLI::Range(0.05, 0.35));
  app.add_option("--pose", rows.pose, "rows mode: the pose followed: fused (odometry, two IMUs, RTK GNSS) or odometry")
      ->check(CLI::IsMember({"fused", "odometry"}));
  app.add_option("--world-realism", rows.world,
                 "rows mode: the plants' realism when it differs from --realism (the sensors'): datasheet plants are "
                 "bodies that slow the physics down many times")
      ->check(CLI::IsMember({"ideal", "datasheet"}));
  app.add_option("--png", rows.png, "rows mode: top view of the field with the driven path");
  app.add_option("--waypoints", rows.waypoints, "rows mode: write the rows' end waypoints (YAML) here");
  app.add_option("--heading-correction-gain", rows.heading_correction_gain,
                 "rows mode: pure pursuit's heading correction gain (PurePursuitParams::heading_correction_gain; 0: "
                 "off, as before 2026-12-07; default fieldRowsConfig's 0.2)");
  app.add_option("--lag-slow-from", rows.lag_slow_from_deg,
                 "rows mode: the rover slows while the articulation lags its set-point by more than this [deg] "
                 "(FieldRowsConfig::lag_slow_from_deg; 0: never, as before 2026-12-07)");
  app.add_option("--trace", rows.trace,
                 "rows mode: a CSV line per control step here (truth, estimate, articulation asked/measured/true, "
                 "pure pursuit's curvature and cross-track)");
  if (const auto code = thorvald_common::parseCommandLine(app, argc, argv)) return *code;
  if (mode == "rows") return runRows(rows, realism_name, c.seed);
  c.realism = *thorvald_sim::realismFromName(realism_name);
  c.calibrate_odometry = !no_calibration;
  if (mode == "outage") {
    c.sets = {SensorSet::kOdometryTwoImusGnss};
    c.outage_start_s = outage_start_s;
    c.outage_s = outage_s;
  }
  FieldLoopResult r;
  try {
    r = cotton_harvester::sim::runFieldLoop(c);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "field_bench: %s\n", e.what());
    return 1;
  }
  std::printf("field_bench --mode %s, realism %s, seed %u\n", mode.c_str(), realism_name.c_str(), c.seed);
  printRows(r);
  const double gnss_err = errorOf(r, SensorSet::kOdometryTwoImusGnss);
  if (mode == "table1") {
    std::printf("RESULT {\"realism\": \"%s\", \"loop_closure_err_m\": %.3f%s}\n", realism_name.c_str(), gnss_err,
                rowKeys(r).c_str());
    return 0;
  }
  const auto& o = *r.outage;
  std::printf(
      "outage %.0f s: error %.3f m when it began, largest %.3f m until the fix was fused again (%.1f s after "
      "it began), largest step of one fix within 30 s of its return %.3f m (at the first RTK-fixed epoch %.3f m), "
      "localization_ok %s throughout\n",
      outage_s, o.error_before_m, o.drift_m, o.fix_gone_s, o.return_step_m, o.fixed_return_step_m,
      o.ok_through_outage ? "true" : "NOT");
  std::printf(
      "RESULT {\"realism\": \"%s\", \"outage_s\": %.0f, \"outage_drift_m\": %.3f, \"outage_return_step_m\": "
      "%.3f, \"fix_return_step_m\": %.3f, \"fixed_return_step_m\": %.3f, \"outage_ok_throughout\": %s, "
      "\"loop_closure_err_m\": %.3f}\n",
      realism_name.c_str(), outage_s, o.drift_m, o.return_step_m, o.return_step_m, o.fixed_return_step_m,
      o.ok_through_outage ? "true" : "false", gnss_err);
  return 0;
}
