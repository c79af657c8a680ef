// field_bench: the cotton rover in a field, headless in MuJoCo. One mode per experiment:
//   --mode table1  the paper's Table 1: a closed loop (20 m legs, two U-turns) on the field-like slope, the
//                  loop-closure error and the estimate's standard deviation of the five sensor sets;
//   --mode outage  the same loop with a 30 s GNSS outage (a tree line) bridged by the IMUs and the odometry.
// Prints a table and one line
//   RESULT {"realism": .., "loop_closure_err_m": .., "<set>_err_m": .., "<set>_sigma_m": .., ...}
// (table1: loop_closure_err_m is odometry + two IMUs + one GNSS's; outage: outage_drift_m, outage_return_step_m).
#include <cmath>
#include <cstdio>
#include <string>

#include <CLI/CLI.hpp>
#include <thorvald_common/command_line.h>

#include "cotton_harvester_sim/field_loop.h"

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
  app.add_option("--mode", mode, "table1 (the five sensor sets) or outage (a GNSS outage on the loop)")
      ->check(CLI::IsMember({"table1", "outage"}));
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
  if (const auto code = thorvald_common::parseCommandLine(app, argc, argv)) return *code;
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
      "it began), largest step of one fix within 30 s of its return %.3f m, localization_ok %s throughout\n",
      outage_s, o.error_before_m, o.drift_m, o.fix_gone_s, o.return_step_m, o.ok_through_outage ? "true" : "NOT");
  std::printf(
      "RESULT {\"realism\": \"%s\", \"outage_s\": %.0f, \"outage_drift_m\": %.3f, \"outage_return_step_m\": "
      "%.3f, \"outage_ok_throughout\": %s, \"loop_closure_err_m\": %.3f}\n",
      realism_name.c_str(), outage_s, o.drift_m, o.return_step_m, o.ok_through_outage ? "true" : "false", gnss_err);
  return 0;
}
