// Map analysis over varied generated headland maps: how many maps are wrong while the analysis says they
// are fine, how many are fully right, origin accuracy, and time against map size.
//   rosrun greenhouse_rail_nav map_analysis_bench [--maps 120] [--seed 7] [--png-dir DIR] [--verbose]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <map>
#include <random>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <thorvald_common/command_line.h>

#include "greenhouse_rail_nav/map_analyzer.h"
#include "greenhouse_rail_nav/map_overlay.h"
#include "greenhouse_rail_nav/testing/synthetic_greenhouse_map.h"

using namespace greenhouse_rail_nav;

namespace {

/// CPU time of this thread [ms]: the figure for "one core", unaffected by other processes on the machine.
double threadMs() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

/// One generated map's conditions, drawn from the bench's random stream.
GreenhouseLayout drawLayout(std::mt19937* rng, int m) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto u = [&]() { return unit(*rng); };
  GreenhouseLayout layout;
  layout.seed = 1000 + static_cast<std::uint32_t>(m);
  // Set counts 4-120, most of them small.
  layout.rail_sets = 4 + static_cast<int>(std::pow(u(), 2.0) * 117);
  layout.spacing_m = 1.4 + 0.6 * u();
  layout.resolution_m = u() < 0.35 ? 0.025 : 0.05;
  layout.headland_depth_m = 3.0 + 3.0 * u();
  layout.visible_row_depth_m = 2.0 + 4.0 * u();
  layout.row_probability = 0.4 + 0.5 * u();
  layout.ventilation_fraction = u();
  layout.gap_probability = 0.5 * u();
  layout.clutter_objects = static_cast<int>(u() * 8);
  layout.clutter_in_line = u() < 0.25;
  layout.noise_lines = u() < 0.25 ? 1 + static_cast<int>(u() * 2) : 0;
  layout.speckle_per_m2 = 0.05 * u();
  layout.speckle_free_fraction = u() < 0.5 ? 0.01 * u() : 0.0;
  layout.door_width_m = u() < 0.2 ? 1.0 + u() : 0.0;
  const double walls = u();
  layout.left_wall = walls > 0.025;  // 5 % of the maps lack one side wall
  layout.right_wall = walls < 0.975;
  layout.floor_beyond_missing_wall_m = 0.3 + 2.0 * u();
  // Half the maps with a missing side wall show the rear wall ending at the corner, half running on over
  // the floor beyond (taken from the map's number, so the other conditions stay as drawn before).
  layout.rear_wall_ends_at_corner = m % 2 == 0;
  layout.layout_in_map = thorvald_base::Pose2D(10.0 * u(), 10.0 * u(), M_PI * (2.0 * u() - 1.0));
  return layout;
}

struct MapScore {
  bool wrong = false;        ///< a good set is off, or a true set is missing without being reported
  bool fully_right = false;  ///< status ok and every true set found as good within the tolerances
  /// Fully right, or (a side wall missing from the map) not wrong, every true set up to the outermost
  /// drawn row on an open side found as good, and the only failed check the side wall: the best answer
  /// the map allows, since nothing in it says how many sets lie beyond that row.
  bool right_as_map_allows = false;
  int good_sets = 0, uncertain_sets = 0;
  double max_across_m = 0.0;
};

/// Scores one analysis against the truth: a reported set matches the true set whose origin is nearest
/// (across the rails); it is off when more than 5 cm across or 0.5 degrees in heading from it.
MapScore score(const GreenhouseLayout& layout, const SyntheticGreenhouseMap& truth, const MapAnalysis& result,
               std::vector<double>* origin_err) {
  const double spacing = layout.spacing_m;
  MapScore out;
  std::vector<bool> matched_good(truth.rail_frames.size(), false);
  const double across_tol = 0.05, heading_tol = 0.5 * M_PI / 180.0;
  std::vector<bool> matched(truth.rail_frames.size(), false);
  for (const auto& set : result.rail_sets) {
    std::size_t best = 0;
    double best_d = 1e18;
    for (std::size_t i = 0; i < truth.rail_frames.size(); ++i) {
      const double d = std::hypot(set.rail_frame.x - truth.rail_frames[i].x, set.rail_frame.y - truth.rail_frames[i].y);
      if (d < best_d) {
        best_d = d;
        best = i;
      }
    }
    const thorvald_base::Pose2D& t = truth.rail_frames[best];
    // Across = perpendicular to the true rails' direction.
    const double across =
        std::abs(-std::sin(t.yaw) * (set.rail_frame.x - t.x) + std::cos(t.yaw) * (set.rail_frame.y - t.y));
    const double heading = std::abs(thorvald_base::normalizeAngle(set.rail_frame.yaw - t.yaw));
    const bool close = across <= across_tol && heading <= heading_tol && best_d < 0.5 * spacing;
    if (set.good) {
      ++out.good_sets;
      out.max_across_m = std::max(out.max_across_m, across);
      if (!close) out.wrong = true;
      if (close) matched_good[best] = true;
      origin_err->push_back(best_d);
    } else {
      ++out.uncertain_sets;
    }
    if (best_d < 0.5 * spacing) matched[best] = true;
  }
  // A true set nobody reported counts as reported when the analysis failed and said so, or when it lies
  // beyond the outermost reported set on a side the analysis marks open (no side wall found there).
  int good_matches = 0;
  for (const auto& set : result.rail_sets) good_matches += set.good;
  const auto first = std::find(matched.begin(), matched.end(), true);
  const auto last = std::find(matched.rbegin(), matched.rend(), true);
  for (std::size_t i = 0; i < truth.rail_frames.size(); ++i) {
    if (matched[i]) continue;
    const bool left_of_all = first == matched.end() || static_cast<std::ptrdiff_t>(i) < first - matched.begin();
    const bool right_of_all = last == matched.rend() || static_cast<std::ptrdiff_t>(i) > matched.rend() - last - 1;
    const bool reported = !result.ok || (left_of_all && result.left_open) || (right_of_all && result.right_open);
    if (!reported) out.wrong = true;
  }
  out.fully_right = result.status == MapStatus::kOk && !out.wrong &&
                    good_matches == static_cast<int>(truth.rail_frames.size()) &&
                    std::all_of(matched.begin(), matched.end(), [](bool b) { return b; });
  out.right_as_map_allows = out.fully_right;
  const bool left_wall = layout.side_walls && layout.left_wall, right_wall = layout.side_walls && layout.right_wall;
  if (!out.fully_right && !out.wrong && result.ok && (!left_wall || !right_wall) && !truth.rows_drawn.empty()) {
    const bool only_walls = std::all_of(result.checks.begin(), result.checks.end(),
                                        [](const AnalysisCheck& c) { return c.passed || c.name == "sides_bounded"; });
    const int first = left_wall ? 0 : truth.rows_drawn.front();
    const int last = right_wall ? layout.rail_sets : truth.rows_drawn.back();
    bool inner_good = true;
    for (int i = first; i < last; ++i) inner_good = inner_good && matched_good[static_cast<std::size_t>(i)];
    out.right_as_map_allows = only_walls && inner_good;
  }
  return out;
}

/// Why a map is not fully right, from the analysis' failed checks and the map's conditions.
std::string causeOf(const GreenhouseLayout& layout, const MapAnalysis& result, const MapScore& s) {
  auto failed = [&](const char* name) {
    return std::any_of(result.checks.begin(), result.checks.end(),
                       [&](const AnalysisCheck& c) { return c.name == name && !c.passed; });
  };
  const bool wall_missing = !(layout.side_walls && layout.left_wall && layout.right_wall);
  if (s.wrong) return "wrong: a good set off or a true set missing unreported";
  if (result.status == MapStatus::kFailed) return "failed: " + result.message;
  if (failed("rear_wall_spans_rows")) return "rear wall shorter than the rows' span";
  if (failed("edge_straight")) return "headland edge not confirmed by the row starts";
  if (failed("spacing_unambiguous")) return "spacing ambiguous (more than one pattern of sets per gap fits)";
  if (failed("spacing_regular")) return "rows and walls not a regular pattern";
  if (failed("spacing_confirmed")) return "spacing from one gap only, not the configured one";
  if (failed("rows_agree_in_heading") || failed("each_row_parallel")) return "rows disagree in heading";
  if (failed("sides_bounded"))
    return wall_missing ? (layout.rear_wall_ends_at_corner
                               ? "side wall missing from the map, rear wall's end not taken as the bound"
                               : "side wall missing from the map, rear wall running on (outer sets uncertain, as "
                                 "they should be)")
                        : "side wall in the map but not found";
  return "sets missing or uncertain with every check passed";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Map analysis over varied generated headland maps (speckle, clutter, gaps, doors, missing walls, "
      "rotations, 4-120 rail sets, 1.4-2.0 m spacing, 5 and 2.5 cm cells) and time against map size"};
  int maps = 120;
  unsigned seed = 7;
  double configured_spacing = 1.60;
  std::string png_dir;
  int only = -1;
  bool verbose = false;
  app.add_option("--maps", maps, "number of generated maps")->check(CLI::Range(1, 100000));
  app.add_option("--seed", seed, "seed of the map conditions");
  app.add_option("--configured-spacing", configured_spacing,
                 "rail_set_spacing_m given to the analyzer for every map [m] (the maps' true spacing varies)")
      ->check(CLI::Range(0.5, 5.0));
  app.add_option("--png-dir", png_dir, "write an overlay PNG of every map that is not fully right into this folder");
  app.add_option("--only", only, "analyse only this map of the set and print every check and warning");
  app.add_flag("--verbose", verbose, "print the cause of every map that is not fully right, and a count per cause");
  if (const auto code = thorvald_common::parseCommandLine(app, argc, argv)) return *code;
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // progress shows when piped

  std::mt19937 rng(seed);
  std::vector<double> origin_err;
  std::map<std::string, int> causes;
  int right_as_allows = 0;
  int wrong = 0, wrong_but_ok = 0, fully_right = 0, uncertain_maps = 0, failed_maps = 0, good_total = 0,
      uncertain_total = 0, true_total = 0;
  std::printf("Map analysis over %d generated maps, configured spacing %.2f m\n\n", maps, configured_spacing);
  std::printf("%4s %5s %5s %5s %6s %5s %5s %-9s %5s %5s %7s %8s  %s\n", "map", "sets", "sp", "res", "rot", "good",
              "unc", "status", "wrong", "right", "acr[m]", "ms", "conditions");
  std::fflush(stdout);
  for (int m = 0; m < maps; ++m) {
    GreenhouseLayout layout = drawLayout(&rng, m);
    auto truth = makeGreenhouseMap(layout);
    // Without at least two rows no map says where the rails start: such maps are drawn again.
    while (truth.rows_drawn.size() < 2) {
      layout.seed += 100000;
      truth = makeGreenhouseMap(layout);
    }
    if (only >= 0 && m != only) continue;
    MapAnalyzerParams params;
    params.rail_set_spacing_m = configured_spacing;
    const double t0 = threadMs();
    const auto result = analyzeMap(truth.map, params);
    const double ms = threadMs() - t0;
    const MapScore s = score(layout, truth, result, &origin_err);
    right_as_allows += s.right_as_map_allows;
    wrong += s.wrong;
    wrong_but_ok += s.wrong;  // a wrong good set or an unreported missing set is wrong whatever the status
    fully_right += s.fully_right;
    uncertain_maps += result.status == MapStatus::kUncertain;
    failed_maps += result.status == MapStatus::kFailed;
    good_total += s.good_sets;
    uncertain_total += s.uncertain_sets;
    true_total += layout.rail_sets;
    std::string conditions = std::to_string(truth.rows_drawn.size()) + " rows";
    if (layout.speckle_free_fraction > 0)
      conditions += ", speckle " + std::to_string(layout.speckle_free_fraction * 100).substr(0, 4) + "%";
    if (layout.clutter_in_line) conditions += ", clutter in line";
    if (layout.noise_lines) conditions += ", noise line";
    if (layout.door_width_m > 0) conditions += ", doors";
    if (!layout.left_wall || !layout.right_wall) conditions += ", wall missing";
    std::printf("%4d %5d %5.2f %5.3f %6.2f %5d %5d %-9s %5s %5s %7.3f %8.1f  %s\n", m, layout.rail_sets,
                layout.spacing_m, layout.resolution_m, layout.layout_in_map.yaw, s.good_sets, s.uncertain_sets,
                toString(result.status), s.wrong ? "WRONG" : "-", s.fully_right ? "yes" : "no", s.max_across_m, ms,
                conditions.c_str());
    if (result.status != MapStatus::kOk && !result.uncertain_reasons.empty())
      std::printf("       %s\n", result.uncertain_reasons.substr(0, 300).c_str());
    if (result.status == MapStatus::kFailed || only >= 0) std::printf("       %s\n", result.message.c_str());
    if (!s.fully_right) {
      const std::string cause = causeOf(layout, result, s);
      ++causes[cause];
      if (verbose) std::printf("       cause: %s\n", cause.c_str());
    }
    if (only >= 0) {
      for (const auto& c : result.checks)
        std::printf("       check %-22s %-4s %.4f (limit %.4f) %s\n", c.name.c_str(), c.passed ? "pass" : "FAIL",
                    c.value, c.limit, c.detail.c_str());
      for (const auto& w : result.warnings) std::printf("       warning: %s\n", w.c_str());
      for (const int i : result.rows) {
        const auto& f = result.lines[static_cast<std::size_t>(i)].fit;
        std::printf("       row line %d: %zu cells, %.2f m long, rms %.3f m, linearity %.4f, centre (%.2f, %.2f)\n", i,
                    f.count, f.length(), f.rms_residual, f.linearity, f.centroid.x(), f.centroid.y());
      }
      for (const auto& set : result.rail_sets)
        if (!set.good) std::printf("       set %d: %s\n", set.index, set.reason.c_str());
    }
    std::fflush(stdout);
    if (!png_dir.empty() && !s.fully_right) {
      std::string error;
      if (!writeMapOverlayPng(truth.map, result, png_dir + "/map_" + std::to_string(m) + ".png", &error))
        std::fprintf(stderr, "%s\n", error.c_str());
    }
  }
  double sum2 = 0.0;
  for (const double e : origin_err) sum2 += e * e;
  const double rms_origin = origin_err.empty() ? NAN : std::sqrt(sum2 / origin_err.size());
  const double fully_right_pct = 100.0 * fully_right / maps;
  const double right_as_allows_pct = 100.0 * right_as_allows / maps;
  std::printf("\nmaps: %d, fully right %d (%.1f %%), uncertain %d, failed %d, wrong %d\n", maps, fully_right,
              fully_right_pct, uncertain_maps, failed_maps, wrong);
  std::printf("rail sets: %d true, %d reported good, %d reported uncertain; good-set origin error RMS %.4f m\n",
              true_total, good_total, uncertain_total, rms_origin);
  std::printf("right as far as the map allows (fully right, or only a side wall missing from the map): %d (%.1f %%)\n",
              right_as_allows, right_as_allows_pct);
  std::printf("maps not fully right, by cause:\n");
  for (const auto& [cause, count] : causes) std::printf("  %4d  %s\n", count, cause.c_str());
  std::fflush(stdout);

  // Time against map size: greenhouses filling maps of about 50x20, 100x40 and 200x60 m at 5 cm.
  std::printf("\n%-14s %10s %10s %8s\n", "map [m]", "cells", "ms", "sets");
  double ms_200x60 = 0.0;
  struct Size {
    double w, h;
  };
  for (const Size sz : {Size{50, 20}, Size{100, 40}, Size{200, 60}}) {
    GreenhouseLayout layout;
    layout.seed = 3;
    layout.spacing_m = 1.6;
    layout.map_margin_m = 1.0;
    layout.rail_sets = static_cast<int>((sz.w - 2.3) / layout.spacing_m);
    layout.headland_depth_m = 5.0;
    layout.visible_row_depth_m = sz.h - 2.0 - 0.15 - layout.headland_depth_m;
    layout.layout_in_map = thorvald_base::Pose2D(0.0, 0.0, 0.0);
    layout.clutter_objects = 6;
    const auto truth = makeGreenhouseMap(layout);
    MapAnalyzerParams params;
    std::vector<double> times;
    std::size_t sets = 0;
    for (int r = 0; r < 3; ++r) {
      const double t0 = threadMs();
      sets = analyzeMap(truth.map, params).rail_sets.size();
      times.push_back(threadMs() - t0);
    }
    std::sort(times.begin(), times.end());
    std::printf("%5.0f x %-6.0f %10d %10.1f %5zu/%d\n", truth.map.widthMeters(), truth.map.heightMeters(),
                truth.map.width * truth.map.height, times[1], sets, layout.rail_sets);
    std::fflush(stdout);
    ms_200x60 = times[1];
  }
  std::printf(
      "RESULT {\"maps\": %d, \"maps_wrong_but_ok\": %d, \"maps_fully_right_pct\": %.1f, \"map_origin_err_m\": %.4f, "
      "\"map_ms_200x60m\": %.1f, \"maps_right_as_map_allows_pct\": %.1f}\n",
      maps, wrong_but_ok, fully_right_pct, rms_origin, ms_200x60, right_as_allows_pct);
  return 0;
}
