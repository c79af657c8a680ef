// The paper's harvest experiments (§2.13, Tables 2 and 3) in MuJoCo: the rover drives a row of cotton plants, its
// camera is rendered by the simulator, perception finds the bolls and the end-effector, the harvest state machine
// moves the rover (deadband-aware position control of the hydrostatic drive) and the arm, and the vacuum takes the
// bolls it really reaches. Potted: six defoliated plants 30 cm apart with three bolls each on a 0.2513 deg slope;
// field: 5.3 m of row on a 2.7668 deg slope. Each run has other plants (seed). Prints a Table 2/3 row per run and
// the averages, why each missed boll was missed (from the simulation's truth), the time per state and the
// end-effector frames, and ends with
//   RESULT {"potted_ct_s": .., "potted_asr_pct": .., "field_ct_s": .., "field_asr_pct": .., "rtf": ..,
//           "ee_fallback_frames": .., "frames": .., "failed_runs": .., "realism": "ideal|datasheet"}
//   rosrun cotton_harvester harvest_bench [--potted-runs 5] [--field-runs 2] [--seed 1] [--png FILE]
//                                          [--realism ideal|datasheet] [--realism-frames FILE]
//                                          [--debug-image FILE] [--verbose] [--no-leaf-clearing] [--ee-whole-image]
//                                          [--no-leaf-push] [--no-partial-bolls]
//                                          [--datasheet-off stereo daylight shadows housing-walls knock-off hood stems]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <thorvald_common/bench_statistics.h>
#include <thorvald_common/command_line.h>

#include "cotton_harvester_sim/harvest_run.h"

using namespace cotton_harvester;

namespace {

double value(const std::optional<double>& v) { return v ? *v : 0.0; }

void printHeader(const char* title) {
  std::printf("\n%s\n%-8s %5s %5s %5s %5s %6s %8s %7s %7s %7s %6s %6s %6s %7s %6s %5s\n", title, "run", "bolls",
              "reach", "det", "tried", "picked", "time_s", "OV_cm/s", "PR_b/s", "CT_s", "ASR%", "DP%", "MRR%",
              "outcome", "frames", "rtf");
}

void printRow(const std::string& name, const sim::HarvestRunReport& r) {
  const auto& c = r.counts;
  const auto& m = r.metrics;
  std::printf("%-8s %5d %5d %5d %5d %6d %8.1f %7.2f %7.3f %7.1f %6.1f %6.1f %6.1f %7s %6d %5.2f\n", name.c_str(),
              r.bolls_present, r.bolls_reachable, c.detected, c.reached, c.picked, c.time_s, m.operation_velocity_cm_s,
              m.production_rate_bolls_s, value(m.cycle_time_s), value(m.action_success_pct),
              value(m.detection_performance_pct), value(m.reaching_ratio_pct), r.outcome.c_str(), r.frames,
              r.wall_time_s > 0 ? r.sim_time_s / r.wall_time_s : 0.0);
  std::fflush(stdout);
}

struct Totals {
  control::HarvestCounts counts;
  int runs = 0, reachable = 0, failed = 0;
  double sim_s = 0.0, wall_s = 0.0;
  sim::MissTable misses;
  std::vector<double> missed_pick_distances_m;  ///< nozzle's closest approach to bolls tried but not taken
  std::map<std::string, double> state_time_s;
  std::map<std::string, int> state_entries;
  int frames = 0, ee_found = 0, ee_rejected = 0, ee_fallback = 0;
  int knocked_off = 0;
  std::vector<double> boll_depth_errors_m, boll_errors_m, effector_depth_errors_m;
  int picks_cleared = 0, picks_redetected = 0, leaves_pushed = 0, leaf_searches = 0, leaf_sweeps = 0;
  void add(const sim::HarvestRunReport& r) {
    ++runs;
    misses.add(r.misses);
    for (size_t i = 0; i < r.miss_causes.size(); ++i) {
      const sim::MissCause c = r.miss_causes[i];
      if ((c == sim::MissCause::kPicksFailed || c == sim::MissCause::kBelievedPicked) &&
          std::isfinite(r.boll_records[i].closest_vacuum_m))
        missed_pick_distances_m.push_back(r.boll_records[i].closest_vacuum_m);
    }
    for (const auto& [state, t] : r.state_time_s) state_time_s[state] += t;
    for (const auto& [state, n] : r.state_entries) state_entries[state] += n;
    frames += r.frames;
    ee_found += r.frames_with_effector;
    ee_rejected += r.effector_rejected;
    ee_fallback += r.effector_from_calibration;
    picks_cleared += r.picks_cleared;
    picks_redetected += r.picks_redetected;
    leaves_pushed += r.leaves_pushed;
    knocked_off += r.bolls_knocked_off;
    for (auto [to, from] : {std::make_pair(&boll_depth_errors_m, &r.boll_depth_errors_m),
                            std::make_pair(&boll_errors_m, &r.boll_errors_m),
                            std::make_pair(&effector_depth_errors_m, &r.effector_depth_errors_m)})
      to->insert(to->end(), from->begin(), from->end());
    leaf_searches += r.leaf_searches;
    leaf_sweeps += r.leaf_sweeps;
    counts.bolls_present += r.bolls_present;
    counts.detected += r.counts.detected;
    counts.reached += r.counts.reached;
    counts.picked += r.counts.picked;
    counts.skipped += r.counts.skipped;
    counts.pick_attempts += r.counts.pick_attempts;
    counts.time_s += r.counts.time_s;
    counts.distance_m += r.counts.distance_m;
    reachable += r.bolls_reachable;
    sim_s += r.sim_time_s;
    wall_s += r.wall_time_s;
    failed += r.error.empty() && r.divergences == 0 ? 0 : 1;
  }
};

void printMisses(const Totals& t) {
  std::printf("misses by cause (%d of %d bolls):", t.misses.misses(), t.counts.bolls_present);
  for (int i = 1; i < static_cast<int>(sim::MissCause::kCount); ++i)
    if (t.misses.count[i] > 0) std::printf("  %s %d", sim::toString(static_cast<sim::MissCause>(i)), t.misses.count[i]);
  std::printf("\n");
  if (!t.missed_pick_distances_m.empty()) {
    std::printf("  nozzle's closest approach to bolls tried but not taken [cm]:");
    for (double d : t.missed_pick_distances_m) std::printf(" %.1f", 100.0 * d);
    std::printf("\n");
  }
}

void printTimes(const Totals& t) {
  const int picked = std::max(1, t.counts.picked);
  std::printf("time by state (s per picked boll, entries):");
  for (const auto& [state, s] : t.state_time_s) {
    const auto n = t.state_entries.find(state);
    std::printf("  %s %.2f (%d)", state.c_str(), s / picked, n == t.state_entries.end() ? 0 : n->second);
  }
  std::printf("\nend-effector: %d frames, found %d, rejected %d, calibrated position used %d\n", t.frames, t.ee_found,
              t.ee_rejected, t.ee_fallback);
  std::printf(
      "leaves: picks that swept leaves aside first %d, of them re-located by a new frame %d; places searched under "
      "the leaves %d, sweeps there %d; leaves pushed %d; bolls knocked off %d\n",
      t.picks_cleared, t.picks_redetected, t.leaf_searches, t.leaf_sweeps, t.leaves_pushed, t.knocked_off);
  // Perception against the truth: median and 10th / 90th percentiles [cm].
  const auto spread = [](const char* what, const std::vector<double>& e) {
    std::printf("  %s: %zu, median %.1f cm (p10 %.1f, p90 %.1f)\n", what, e.size(),
                100.0 * thorvald_common::percentile(e, 0.5), 100.0 * thorvald_common::percentile(e, 0.1),
                100.0 * thorvald_common::percentile(e, 0.9));
  };
  std::printf("perception against the truth, per frame:\n");
  spread("matched detections' depth minus the boll's true top", t.boll_depth_errors_m);
  spread("matched detections' 3D distance from the boll's true top", t.boll_errors_m);
  spread("end-effector's measured depth minus its true top face", t.effector_depth_errors_m);
  std::fflush(stdout);
}

/// Runs `runs` harvests of one experiment, prints their rows and the pooled row (metrics of the summed counts).
bool verbose = false;
int potted_plants = 6;
std::string frames_dir;
bool clear_leaves = true;
bool ee_near_arm = true;
bool leaf_push = true;
bool partial_bolls = true;
bool search_leaves = true;
thorvald_sim::Realism realism = thorvald_sim::Realism::kDatasheet;
sim::DatasheetParts datasheet_parts;

control::HarvestMetrics experiment(const char* title, bool field, int runs, unsigned seed, Totals* totals,
                                   const std::string& png, const std::string& debug_image) {
  printHeader(title);
  Totals t;
  for (int i = 0; i < runs; ++i) {
    sim::HarvestRunConfig config = field ? sim::fieldConfig(seed + i) : sim::pottedConfig(seed + i);
    if (!field && potted_plants != 6) {
      config.sim.row.plants = potted_plants;
      config.machine.row_length_m = 1.6 + 0.3 * potted_plants - 0.3;
    }
    config.sim.realism = realism;
    config.sim.parts = datasheet_parts;
    if (i == 0) config.debug_image_path = debug_image;
    config.verbose = verbose;
    config.machine.actions.clear_leaves_before_pick = clear_leaves;
    if (!search_leaves) config.machine.search_under_leaves = false;
    config.effector_search_near_arm = ee_near_arm;
    config.partial_bolls = partial_bolls;
    if (!leaf_push) config.sim.leaf_push_max_m = 0.0;
    if (i == 0 && !field) config.frames_dir = frames_dir;
    const sim::HarvestRunReport r = runHarvest(config);
    if (!r.error.empty()) std::printf("run %d failed: %s\n", i + 1, r.error.c_str());
    if (verbose) {
      std::fprintf(stderr, "run %d: encoder travel minus true travel at the end %.3f m\n", i + 1, r.odometry_error_m);
      for (size_t b = 0; b < r.miss_causes.size() && b < r.bolls.size(); ++b) {
        if (r.miss_causes[b] == sim::MissCause::kCaptured) continue;
        const sim::BollRecord& rec = r.boll_records[b];
        std::fprintf(stderr,
                     "missed boll %zu (plant %d, x %.2f y %.2f z %.2f): %s; in view %d frames, detected %d (reachable "
                     "%d), best visible %.0f %%, nozzle closest %.1f cm, best along the row %.0f %%\n",
                     b, r.bolls[b].plant, r.bolls[b].centre.x(), r.bolls[b].centre.y(), r.bolls[b].centre.z(),
                     sim::toString(r.miss_causes[b]), rec.frames_in_view, rec.frames_detected,
                     rec.frames_detected_reachable, 100.0 * rec.max_visible_fraction, 100.0 * rec.closest_vacuum_m,
                     100.0 * rec.row_best_visible_fraction);
      }
    }
    printRow("run" + std::to_string(i + 1), r);
    if (i == 0 && !png.empty() && !writePathPng(r, png)) std::printf("could not write %s\n", png.c_str());
    t.add(r);
  }
  const control::HarvestMetrics m = control::computeMetrics(t.counts);
  sim::HarvestRunReport pooled;
  pooled.counts = t.counts;
  pooled.metrics = m;
  pooled.bolls_present = t.counts.bolls_present;
  pooled.bolls_reachable = t.reachable;
  pooled.outcome = "-";
  pooled.sim_time_s = t.sim_s;
  pooled.wall_time_s = t.wall_s;
  printRow("all", pooled);
  printMisses(t);
  printTimes(t);
  totals->sim_s += t.sim_s;
  totals->ee_fallback += t.ee_fallback;
  totals->frames += t.frames;
  totals->wall_s += t.wall_s;
  totals->failed += t.failed;
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Harvest of simulated cotton rows in MuJoCo (paper Tables 2 and 3)"};
  int potted_runs = 5, field_runs = 2;
  unsigned seed = 1;
  std::string png, debug_image;
  app.add_option("--potted-runs", potted_runs, "runs of the potted test (Table 2)")->check(CLI::Range(0, 100));
  app.add_option("--field-runs", field_runs, "runs of the field-like test (Table 3)")->check(CLI::Range(0, 100));
  app.add_option("--seed", seed, "seed of the first run's plants");
  app.add_option("--png", png, "top view of the first potted run: path, picked and missed bolls");
  app.add_option("--debug-image", debug_image, "camera frame of the first potted run with its detections");
  app.add_option("--potted-plants", potted_plants, "plants of the potted row (the paper: 6)")->check(CLI::Range(1, 60));
  app.add_option("--frames-dir", frames_dir, "write every frame of the first potted run with its detections here");
  std::string realism_name = "datasheet", realism_frames;
  app.add_option(
         "--realism", realism_name,
         "the cotton world and camera: datasheet (the default) or ideal (flat-coloured plants, small depth noise)")
      ->check(CLI::IsMember({"ideal", "datasheet"}));
  app.add_option("--realism-frames", realism_frames,
                 "write the potted row's camera frame in ideal and datasheet side by side (colour over depth) as PNG "
                 "and end");
  std::vector<std::string> parts_off;
  app.add_option("--datasheet-off", parts_off,
                 "datasheet parts to switch off (to measure each one's cost): stereo, daylight, shadows, "
                 "housing-walls, knock-off, hood (the housing a solid box), stems (the housing passes through stems "
                 "and branches)")
      ->check(CLI::IsMember({"stereo", "daylight", "shadows", "housing-walls", "knock-off", "hood", "stems"}));
  app.add_flag("--verbose", verbose, "print the state machine's transitions");
  bool no_clear = false, ee_whole = false, no_push = false, no_partial = false, no_search = false;
  app.add_flag("--no-leaf-search", no_search, "pass on without looking under the leaves (field-like runs)");
  app.add_flag("--no-partial-bolls", no_partial, "the colour detector drops bolls seen only in part");
  app.add_flag("--no-leaf-clearing", no_clear, "pick without sweeping leaves over the boll aside first");
  app.add_flag("--ee-whole-image", ee_whole, "take the largest orange region of the image as the end-effector");
  app.add_flag("--no-leaf-push", no_push, "simulated leaves do not give way to the housing");
  if (const auto code = thorvald_common::parseCommandLine(app, argc, argv)) return *code;
  clear_leaves = !no_clear;
  ee_near_arm = !ee_whole;
  leaf_push = !no_push;
  partial_bolls = !no_partial;
  search_leaves = !no_search;
  realism = *thorvald_sim::realismFromName(realism_name);
  for (const std::string& part : parts_off) {
    if (part == "stereo") datasheet_parts.passive_stereo = false;
    if (part == "daylight") datasheet_parts.daylight = false;
    if (part == "shadows") datasheet_parts.shadows = false;
    if (part == "housing-walls") datasheet_parts.housing_meets_bolls = false;
    if (part == "knock-off") datasheet_parts.knock_off = false;
    if (part == "hood") datasheet_parts.hood_housing = false;
    if (part == "stems") datasheet_parts.housing_meets_stems = false;
  }
  if (!realism_frames.empty()) {
    const bool ok = sim::writeRealismFrames(sim::pottedConfig(seed).sim, realism_frames);
    std::printf(ok ? "wrote %s\n" : "could not write %s\n", realism_frames.c_str());
    return ok ? 0 : 1;
  }

  Totals totals;
  control::HarvestMetrics potted, field;
  if (potted_runs > 0)
    potted = experiment("Table 2: potted, defoliated (6 plants x 3 bolls, slope 0.2513 deg)", false, potted_runs, seed,
                        &totals, png, debug_image);
  if (field_runs > 0)
    field = experiment("Table 3: field-like (5.3 m of row, slope 2.7668 deg)", true, field_runs, seed + 100, &totals,
                       "", "");
  std::printf("\npaper: potted CT 17.3 s, ASR 88.9 %%, DP 96.7 %%, MRR 94.4 %%; field CT 38.4 s, ASR 78.6 %%\n");
  std::printf(
      "RESULT {\"potted_ct_s\": %.2f, \"potted_asr_pct\": %.1f, \"field_ct_s\": %.2f, \"field_asr_pct\": %.1f, "
      "\"rtf\": %.2f, \"ee_fallback_frames\": %d, \"frames\": %d, \"failed_runs\": %d, \"realism\": \"%s\"}\n",
      value(potted.cycle_time_s), value(potted.action_success_pct), value(field.cycle_time_s),
      value(field.action_success_pct), totals.wall_s > 0 ? totals.sim_s / totals.wall_s : 0.0, totals.ee_fallback,
      totals.frames, totals.failed, thorvald_sim::realismName(realism));
  return totals.failed == 0 ? 0 : 1;
}
