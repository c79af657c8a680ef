// Map analysis accuracy over varied synthetic greenhouse maps, and time against map size.
//   rosrun greenhouse_rail_nav map_analysis_bench [maps=40]
#include <algorithm>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <vector>

#include "greenhouse_rail_nav/map_analyzer.h"
#include "greenhouse_rail_nav/synthetic_greenhouse_map.h"

using greenhouse_rail_nav::analyzeMap;
using greenhouse_rail_nav::GreenhouseLayout;
using greenhouse_rail_nav::MapAnalyzerParams;
using greenhouse_rail_nav::normalizeAngle;
using greenhouse_rail_nav::Pose2D;

namespace {

/// CPU time of this thread [ms]: the figure for "one core", unaffected by other processes on the machine.
double threadMs() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

}  // namespace

int main(int argc, char** argv) {
  const int maps = argc > 1 ? std::max(1, std::atoi(argv[1])) : 40;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double sum_origin2 = 0.0, sum_heading2 = 0.0, max_origin = 0.0, max_heading = 0.0;
  int sets_compared = 0, count_ok = 0, failed = 0, nothing_to_find = 0;
  std::printf("Map analysis over %d varied synthetic maps (5 cm cells)\n\n", maps);
  std::printf("%4s %5s %7s %6s %5s %6s %6s %9s %9s %8s\n", "map", "sets", "found", "rot", "rows", "clutr", "size",
              "rms_o[m]", "max_h[r]", "ms");
  for (int m = 0; m < maps; ++m) {
    GreenhouseLayout layout;
    layout.seed = 100 + static_cast<std::uint32_t>(m);
    layout.rail_sets = 3 + static_cast<int>(unit(rng) * 28);
    layout.spacing_m = 1.4 + 0.4 * unit(rng);
    layout.headland_depth_m = 3.0 + 3.0 * unit(rng);
    layout.visible_row_depth_m = 2.0 + 4.0 * unit(rng);
    layout.row_probability = 0.3 + 0.5 * unit(rng);
    layout.clutter_objects = static_cast<int>(unit(rng) * 8);
    layout.speckle_per_m2 = 0.05 * unit(rng);
    layout.layout_in_map = Pose2D(10.0 * unit(rng), 10.0 * unit(rng), M_PI * (2.0 * unit(rng) - 1.0));
    const auto truth = greenhouse_rail_nav::makeGreenhouseMap(layout);
    MapAnalyzerParams params;
    params.rail_set_spacing_m = layout.spacing_m;
    const double t0 = threadMs();
    const auto result = analyzeMap(truth.map, params);
    const double ms = (threadMs() - t0);
    double map_sum = 0.0, map_max_h = 0.0;
    const bool same_count = result.rail_sets.size() == truth.rail_frames.size();
    if (!result.ok) ++failed;
    if (truth.rows_drawn.empty()) ++nothing_to_find;
    if (same_count) {
      ++count_ok;
      for (std::size_t i = 0; i < truth.rail_frames.size(); ++i) {
        const Pose2D& est = result.rail_sets[i].rail_frame;
        const Pose2D& tru = truth.rail_frames[i];
        const double e = std::hypot(est.x - tru.x, est.y - tru.y);
        const double h = std::abs(normalizeAngle(est.yaw - tru.yaw));
        sum_origin2 += e * e;
        sum_heading2 += h * h;
        map_sum += e * e;
        max_origin = std::max(max_origin, e);
        max_heading = std::max(max_heading, h);
        map_max_h = std::max(map_max_h, h);
        ++sets_compared;
      }
    }
    std::printf("%4d %5d %7zu %6.2f %5zu %6d %3.0fx%-3.0f %9.4f %9.4f %8.1f\n", m, layout.rail_sets,
                result.rail_sets.size(), layout.layout_in_map.yaw, truth.rows_drawn.size(), layout.clutter_objects,
                truth.map.widthMeters(), truth.map.heightMeters(),
                same_count ? std::sqrt(map_sum / truth.rail_frames.size()) : NAN, same_count ? map_max_h : NAN, ms);
  }
  const double rms_origin = sets_compared ? std::sqrt(sum_origin2 / sets_compared) : NAN;
  const double rms_heading = sets_compared ? std::sqrt(sum_heading2 / sets_compared) : NAN;
  std::printf(
      "\nmaps with the right number of rail sets: %d / %d (no poses given: %d; maps without any row drawn: %d)\n",
      count_ok, maps, failed, nothing_to_find);
  std::printf("rail frames compared: %d, origin error RMS %.4f m (max %.4f), heading error RMS %.5f rad (max %.5f)\n",
              sets_compared, rms_origin, max_origin, rms_heading, max_heading);

  // Time against map size: greenhouses filling maps of about 50x20, 100x40 and 200x60 m, rotated 0.3 rad
  // for the first two; the largest is axis-aligned so the grid is exactly the size asked for.
  std::printf("\n%-14s %10s %10s %8s\n", "map [m]", "cells", "ms", "sets");
  double ms_200x60 = 0.0;
  struct Size {
    double w, h;
  };
  for (const Size s : {Size{50, 20}, Size{100, 40}, Size{200, 60}}) {
    GreenhouseLayout layout;
    layout.seed = 3;
    layout.spacing_m = 1.6;
    layout.map_margin_m = 1.0;
    layout.rail_sets = static_cast<int>((s.w - 2.3) / layout.spacing_m);
    layout.headland_depth_m = 5.0;
    layout.visible_row_depth_m = s.h - 2.0 - 0.15 - layout.headland_depth_m;
    layout.layout_in_map = Pose2D(0.0, 0.0, 0.0);
    layout.clutter_objects = 6;
    const auto truth = greenhouse_rail_nav::makeGreenhouseMap(layout);
    MapAnalyzerParams params;
    std::vector<double> times;
    std::size_t sets = 0;
    for (int r = 0; r < 3; ++r) {
      const double t0 = threadMs();
      sets = analyzeMap(truth.map, params).rail_sets.size();
      times.push_back((threadMs() - t0));
    }
    std::sort(times.begin(), times.end());
    std::printf("%5.0f x %-6.0f %10d %10.1f %5zu/%d\n", truth.map.widthMeters(), truth.map.heightMeters(),
                truth.map.width * truth.map.height, times[1], sets, layout.rail_sets);
    ms_200x60 = times[1];
  }
  std::printf("RESULT {\"map_origin_err_m\": %.4f, \"map_heading_err_rad\": %.5f, \"map_ms_200x60m\": %.1f}\n",
              rms_origin, rms_heading, ms_200x60);
  return 0;
}
