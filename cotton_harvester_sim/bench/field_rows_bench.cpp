// field_rows_bench: the cotton rover follows the rows of a field and turns at their ends, headless in MuJoCo
// (field_rows.h: pure pursuit and omega turns through the rover's own controller on its wheel odometry; the truth
// only scores). Prints a line per row and per turn, then
//   RESULT {"realism": .., "rows": .., "row_length_m": .., "cross_track_rms_m": .., "row_end_turn_success_pct": ..,
//           "rows_completed_pct": .., ...}
//   field_rows_bench                          (4 rows x 20 m, the field)
//   field_rows_bench --rows 2 --length 4 --png /tmp/field.png --waypoints /tmp/field_rows.yaml
#include <cstdio>
#include <string>

#include <CLI/CLI.hpp>
#include <thorvald_common/command_line.h>

#include "cotton_harvester_sim/field_rows.h"

int main(int argc, char** argv) {
  CLI::App app("field_rows_bench: rows followed and turned in MuJoCo");
  int rows = 4;
  double length = 20.0;
  unsigned seed = 1;
  std::string realism_name = "ideal", png, waypoints;
  double speed = 0.25;
  app.add_option("--rows", rows, "rows in the field")->check(CLI::Range(1, 40));
  app.add_option("--length", length, "row length [m]")->check(CLI::Range(0.5, 200.0));
  app.add_option("--seed", seed, "the plants");
  app.add_option("--speed", speed, "harvest speed along the rows [m/s]")->check(CLI::Range(0.05, 0.35));
  app.add_option("--realism", realism_name, "the world: ideal or datasheet")
      ->check(CLI::IsMember({"ideal", "datasheet"}));
  app.add_option("--png", png, "top view of the field with the driven path");
  app.add_option("--waypoints", waypoints, "write the rows' end waypoints (YAML) here");
  if (const auto code = thorvald_common::parseCommandLine(app, argc, argv)) return *code;

  cotton_harvester::sim::FieldRowsConfig c = cotton_harvester::sim::fieldRowsConfig(rows, length, seed);
  c.sim.realism = *thorvald_sim::realismFromName(realism_name);
  c.row_speed_mps = speed;
  c.rover.max_speed_mps = std::max(c.rover.max_speed_mps, speed);
  c.waypoints_path = waypoints;
  c.time_limit_s = 600.0 + rows * (length / speed + 120.0);
  c.progress = [](const std::string& line) { std::printf("%s\n", line.c_str()); };
  const cotton_harvester::sim::FieldRowsReport r = cotton_harvester::sim::runFieldRows(c);
  for (const auto& row : r.rows)
    std::printf("row %d: %s, cross-track rms %.3f m, max %.3f m, odometry off by %.2f m at its end, %.0f s\n", row.row,
                row.completed ? "completed" : "NOT completed", row.cross_track_rms_m, row.cross_track_max_m,
                row.odometry_error_m, row.time_s);
  for (const auto& t : r.turns)
    std::printf("turn after row %d: %s, entry %.3f m / %.1f deg, %.2f m deep (planned %.2f)\n", t.from_row,
                t.success ? "entered" : "FAILED", t.entry_cross_track_m, t.entry_heading_deg, t.depth_m,
                t.planned_depth_m);
  if (!r.error.empty()) std::printf("error: %s\n", r.error.c_str());
  if (!png.empty() && !cotton_harvester::sim::writeFieldPng(r, png)) std::printf("could not write %s\n", png.c_str());
  std::printf(
      "RESULT {\"realism\": \"%s\", \"rows\": %d, \"row_length_m\": %.1f, \"speed_mps\": %.2f, \"cross_track_rms_m\": "
      "%.4f, \"row_end_turn_success_pct\": %.1f, \"rows_completed_pct\": %.1f, \"sim_s\": %.1f, \"wall_s\": %.1f}\n",
      realism_name.c_str(), rows, length, speed, r.cross_track_rms_m, r.turn_success_pct, r.rows_completed_pct,
      r.sim_time_s, r.wall_time_s);
  return r.error.empty() ? 0 : 1;
}
