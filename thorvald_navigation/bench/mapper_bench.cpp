// Time per integrated scan of the headland mapper (OccupancyMapper) on a synthetic headland: 541 beams of 270 deg,
// 25 m, 2.5 cm cells as the greenhouse configuration runs it, driven back and forth along the headland with exact
// odometry. Prints the table and a RESULT line: CPU milliseconds of this thread per integrated scan (mean, p95, max;
// CPU time, so that other work on the machine does not count) and the pose error at the end, so that a faster
// mapper that maps worse shows it.
#include <algorithm>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <CLI/CLI.hpp>
#include <thorvald_common/command_line.h>

#include "thorvald_navigation/occupancy_mapper.h"
#include "thorvald_navigation/testing/synthetic_headland.h"

namespace tn = thorvald_navigation;

namespace {

double threadCpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return 1e3 * static_cast<double>(ts.tv_sec) + 1e-6 * static_cast<double>(ts.tv_nsec);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Milliseconds per integrated scan of the headland mapper on a synthetic headland"};
  double length_m = 20.0, resolution_m = 0.025, max_range_m = 25.0;
  std::uint32_t seed = 1;
  app.add_option("--length", length_m, "headland length [m]")->check(CLI::Range(6.0, 100.0));
  app.add_option("--resolution", resolution_m, "cell size [m]")->check(CLI::Range(0.0125, 0.2));
  app.add_option("--max-range", max_range_m, "mapper max range [m]")->check(CLI::Range(2.0, 30.0));
  app.add_option("--seed", seed, "random seed");
  bool match_surface = false;
  app.add_flag("--match-surface", match_surface, "match at the walls' surface (headland_mapper's match_surface)");
  if (const auto code = thorvald_common::parseCommandLine(app, argc, argv)) return *code;

  tn::testing::HeadlandOptions o;
  o.length_m = length_m;
  o.seed = seed;
  const tn::testing::SyntheticHeadland world(o);
  tn::MapperParams p;
  p.match_surface = match_surface;
  p.resolution_m = resolution_m;
  p.max_range_m = max_range_m;
  tn::OccupancyMapper mapper(p);
  std::mt19937 rng(seed);
  const Eigen::Vector2d sensor(0.45, 0.0);
  const thorvald_base::Pose2D start{1.5, o.depth_m - 0.7, 0.0};
  thorvald_base::Pose2D truth = start, odom{};
  const double dt = 0.05, v = 0.5, w = 0.5;
  const double straight_s = (o.length_m - 3.0) / v, turn_s = thorvald_base::kPi / w;
  const double legs[][3] = {{v, 0.0, straight_s}, {0.0, w, turn_s}, {v, 0.0, straight_s}, {0.0, -w, turn_s}};
  std::vector<double> ms;
  std::printf("  headland %.0f m, cells %.4f m, beams 541 to %.0f m\n", length_m, resolution_m, max_range_m);
  for (const auto& leg : legs) {
    for (double t = 0.0; t < leg[2] - 1e-9; t += dt) {
      truth = truth * thorvald_base::Pose2D{leg[0] * dt, 0.0, leg[1] * dt};
      odom = odom * thorvald_base::Pose2D{leg[0] * dt, 0.0, leg[1] * dt};
      const auto pts = world.scan(truth, sensor, 541, -2.356, 2.356, 30.0, 0.01, &rng);
      const double t0 = threadCpuMs();
      const tn::MapperUpdate u = mapper.addScan(odom, sensor, pts, {});
      const double elapsed = threadCpuMs() - t0;
      if (u.integrated) ms.push_back(elapsed);
    }
    std::printf("  leg done: %d scans integrated, %.1f m2 mapped\n", mapper.scansUsed(), mapper.knownAreaM2());
    std::fflush(stdout);
  }
  const thorvald_base::Pose2D est = mapper.mapToOdom() * odom, truth_in_map = start.inverse() * truth;
  const double err = std::hypot(est.x - truth_in_map.x, est.y - truth_in_map.y);
  double sum = 0.0;
  for (double m : ms) sum += m;
  std::vector<double> sorted = ms;
  std::sort(sorted.begin(), sorted.end());
  const double mean = ms.empty() ? 0.0 : sum / ms.size();
  const double p95 = sorted.empty() ? 0.0 : sorted[static_cast<std::size_t>(0.95 * (sorted.size() - 1))];
  const double max = sorted.empty() ? 0.0 : sorted.back();
  std::printf("  %zu scans integrated: CPU %.1f ms mean, %.1f ms p95, %.1f ms max; final pose error %.4f m\n",
              ms.size(), mean, p95, max, err);
  std::printf(
      "RESULT {\"world\": \"synthetic_headland\", \"length_m\": %.1f, \"resolution_m\": %.4f, \"scans_integrated\": "
      "%zu, \"mapper_ms_per_scan\": %.2f, \"mapper_ms_per_scan_p95\": %.2f, \"mapper_ms_per_scan_max\": %.2f, "
      "\"final_pose_err_m\": %.4f}\n",
      length_m, resolution_m, ms.size(), mean, p95, max, err);
  return 0;
}
