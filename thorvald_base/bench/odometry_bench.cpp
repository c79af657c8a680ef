// Odometry accuracy of the two estimators on the same simulated drive: the Figure 7 robot driving the paper's
// 77 s loop, readings corrupted alike (quantisation, noise, 1% radius error on two wheels, one slipping wheel).
// Usage: odometry_bench [--seeds N] [--csv path.csv] [--png paths.png]   (--help for details)
#include <CLI/CLI.hpp>
#include <thorvald_common/command_line.h>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>

#include "thorvald_base/testing/odometry_trial.h"

int main(int argc, char** argv) {
  int seeds = 5;
  std::string csv, png;
  CLI::App app("Odometry accuracy of the least-squares and the paper's random-pairs estimators on the Figure 7 robot",
               "odometry_bench");
  app.add_option("--seeds", seeds, "number of seeds (1, 2, ...)")->check(CLI::Range(1, 1000))->capture_default_str();
  app.add_option("--csv", csv, "write the three paths of the first seed to this CSV file");
  app.add_option("--png", png, "draw the paths of all seeds into this PNG (matplotlib, /usr/bin/python3)");
  if (const auto code = thorvald_common::parseCommandLine(app, argc, argv)) return *code;
  const auto robot = thorvald_base::figure7Robot();
  const auto loop = thorvald_base::paperLoop();
  const thorvald_base::TrialCorruption corruption;
  std::printf(
      "Figure 7 robot, %zu-segment loop, readings: encoder quantisation, speed noise %.3f rad/s, steering "
      "noise %.4f rad, +%.0f%% radius on drives 1 and 4, drive %d slips %.0f%% (%.0f%% of the time)\n",
      loop.size(), corruption.speed_noise_radps, corruption.steering_noise_rad, 100 * corruption.radius_error,
      corruption.slipping_drive, 100 * corruption.slip_ratio, 100 * corruption.slip_fraction);
  std::printf("%-6s %12s %12s %12s %14s %14s\n", "seed", "truth [m]", "ls [m]", "paper [m]", "ls err [%]",
              "paper err [%]");
  double sum_ls = 0, sum_paper = 0, sum_dist = 0;
  const std::string all_paths = png.empty() ? "" : png + ".csv";
  std::ofstream paths;
  if (!all_paths.empty()) {
    paths.open(all_paths);
    if (!paths) {
      std::fprintf(stderr, "odometry_bench: cannot write %s\n", all_paths.c_str());
      return 1;
    }
    paths << "seed,t,truth_x,truth_y,ls_x,ls_y,paper_x,paper_y\n";
  }
  for (int s = 1; s <= seeds; ++s) {
    const auto r = thorvald_base::runOdometryTrial(robot, loop, corruption, static_cast<unsigned>(s));
    std::printf("%-6d %12.2f %12.2f %12.2f %14.3f %14.3f\n", s, r.distance_truth_m, r.distance_ls_m, r.distance_paper_m,
                r.errorPctLs(), r.errorPctPaper());
    std::fflush(stdout);  // progress when piped
    for (const auto& p : r.path) {
      if (!paths.is_open()) break;
      paths << s << ',' << p.t << ',' << p.truth.x << ',' << p.truth.y << ',' << p.least_squares.x << ','
            << p.least_squares.y << ',' << p.paper.x << ',' << p.paper.y << '\n';
    }
    sum_ls += r.errorPctLs();
    sum_paper += r.errorPctPaper();
    sum_dist += r.distance_truth_m;
    if (s == 1 && !csv.empty()) {
      std::ofstream out(csv);
      out << "t,truth_x,truth_y,ls_x,ls_y,paper_x,paper_y\n";
      for (const auto& p : r.path) {
        out << p.t << ',' << p.truth.x << ',' << p.truth.y << ',' << p.least_squares.x << ',' << p.least_squares.y
            << ',' << p.paper.x << ',' << p.paper.y << '\n';
      }
    }
  }
  if (paths.is_open()) {
    paths.close();
    const std::string cmd =
        std::string("/usr/bin/python3 '") + ODOMETRY_PLOT_SCRIPT + "' '" + all_paths + "' '" + png + "'";
    if (std::system(cmd.c_str()) != 0) {
      std::fprintf(stderr, "odometry_bench: drawing %s failed (needs python3-matplotlib)\n", png.c_str());
      return 1;
    }
    std::remove(all_paths.c_str());
    std::printf("paths of %d seeds drawn into %s\n", seeds, png.c_str());
  }
  const double ls = sum_ls / seeds, paper = sum_paper / seeds;
  std::printf(
      "mean over %d seeds: distance %.2f m, end-point error least squares %.3f %%, paper %.3f %%, "
      "paper/ls %.2f (the paper's robot: 2.2 m over 80.2 m = 2.74 %%)\n",
      seeds, sum_dist / seeds, ls, paper, paper / ls);
  std::printf(
      "RESULT {\"odom_err_pct_ls\": %.4f, \"odom_err_pct_paper\": %.4f, \"paper_over_ls\": %.3f, "
      "\"distance_m\": %.2f}\n",
      ls, paper, paper / ls, sum_dist / seeds);
  return 0;
}
