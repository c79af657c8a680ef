// headland_bench: localisation accuracy and cost, and navigation to random goals, on synthetic headlands with a
// kinematic robot (no MuJoCo: the simulator figures are not measured here). Prints a table and a final
// `RESULT {json}` line.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <CLI/CLI.hpp>
#include <thorvald_common/bench_statistics.h>
#include <thorvald_common/command_line.h>

#include "thorvald_navigation/costmap.h"
#include "thorvald_navigation/grid_planner.h"
#include "thorvald_navigation/map_localizer.h"
#include "thorvald_navigation/path_follower.h"
#include "thorvald_navigation/testing/synthetic_headland.h"

namespace tn = thorvald_navigation;

namespace {

const Eigen::Vector2d kSensor(0.45, 0.0);

using thorvald_common::percentile;

struct LocResult {
  double rms_xy = 0, rms_yaw = 0, ms_per_scan = 0;
  int scans = 0;
};

// Drives back and forth along the headland for `seconds` at 40 Hz scans, odometry with 2 % scale and yaw-rate
// errors, localising in a 2.5 cm map of the same headland.
LocResult localise(std::uint32_t seed, double seconds) {
  tn::testing::HeadlandOptions o;
  o.seed = seed;
  const tn::testing::SyntheticHeadland world(o);
  tn::MapLocalizer loc{tn::LocalizerParams{}};
  loc.setMap(world.truthMap(0.025));
  std::mt19937 rng(seed);
  thorvald_base::Pose2D truth{2.0, o.depth_m - 0.9, 0.0}, odom{};
  loc.setPose(truth, odom);
  tn::FollowerParams fp;
  fp.max_speed_mps = 0.5;
  tn::PathFollower follower(fp);
  bool east = true;
  const double dt = 0.025;
  double sxy = 0, syaw = 0, ms = 0;
  LocResult r;
  for (double t = 0.0; t < seconds; t += dt) {
    if (follower.state() == tn::FollowState::kArrived) {
      const thorvald_base::Pose2D goal{east ? o.length_m - 2.0 : 2.0, o.depth_m - 0.9, east ? 0.0 : thorvald_base::kPi};
      follower.setPath({{truth.x, truth.y}, {goal.x, goal.y}}, goal);
      east = !east;
    }
    const thorvald_base::Twist2D c = follower.step(truth, dt);
    truth = truth * thorvald_base::Pose2D{c.vx * dt, 0.0, c.wz * dt};
    odom = odom * thorvald_base::Pose2D{c.vx * 1.02 * dt, 0.0, (c.wz * 1.02 + 0.005) * dt};
    const auto pts = world.scan(truth, kSensor, 1081, -2.356, 2.356, 30.0, 0.01, &rng);
    const auto t0 = std::chrono::steady_clock::now();
    const tn::LocalizationUpdate u = loc.update(odom, pts);
    ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const double e = std::hypot(u.pose.x - truth.x, u.pose.y - truth.y),
                 ey = thorvald_base::normalizeAngle(u.pose.yaw - truth.yaw);
    sxy += e * e;
    syaw += ey * ey;
    ++r.scans;
  }
  r.rms_xy = std::sqrt(sxy / r.scans);
  r.rms_yaw = std::sqrt(syaw / r.scans);
  r.ms_per_scan = ms / r.scans;
  return r;
}

struct NavResult {
  int goals = 0, reached = 0;
  std::vector<double> err_xy, err_yaw, ratio;
};

// Random start and goal poses on the headland floor, planned on a 5 cm map with a 0.2 m deep keep-out band at the
// rows, followed by a differential robot that executes commands with a lag.
NavResult navigate(std::uint32_t seed, int goals) {
  NavResult r;
  tn::testing::HeadlandOptions o;
  o.seed = seed;
  const tn::testing::SyntheticHeadland world(o);
  const thorvald_map::OccupancyGrid map = world.truthMap(0.05);
  thorvald_map::OccupancyGrid keep_out(map.width, map.height, map.resolution_m, map.origin.x, map.origin.y,
                                       thorvald_map::kFree);
  for (int y = 0; y < map.height; ++y)
    for (int x = 0; x < map.width; ++x)
      if (map.cellCentre(x, y).y() > o.depth_m - 0.2) keep_out.at(x, y) = thorvald_map::kOccupied;
  tn::CostmapParams cp;
  cp.planning_radius_m = 0.39;
  const tn::Costmap cm(map, keep_out, cp);
  const tn::Footprint fp = tn::rectangleFootprint(-0.91, 0.23, -0.39, 0.39);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> ux(1.0, o.length_m - 1.0), uy(0.5, o.depth_m - 0.5),
      uyaw(-thorvald_base::kPi, thorvald_base::kPi);
  auto freePose = [&] {
    for (;;) {
      const thorvald_base::Pose2D p{ux(rng), uy(rng), uyaw(rng)};
      const Eigen::Vector2i c = cm.geometry().cellOf({p.x, p.y});
      if (cm.cost(c.x(), c.y()) < tn::kInscribedCost && cm.footprintBlocker(p, fp) == tn::Blocker::kNone) return p;
    }
  };
  for (int g = 0; g < goals; ++g) {
    thorvald_base::Pose2D pose = freePose();
    const thorvald_base::Pose2D goal = freePose();
    ++r.goals;
    const tn::PlanResult plan = tn::planPath(cm, {pose.x, pose.y}, {goal.x, goal.y}, tn::PlannerParams{});
    if (!plan.ok) continue;
    tn::PathFollower f{tn::FollowerParams{}};
    f.setPath(plan.path, goal);
    thorvald_base::Twist2D actual;
    double driven = 0.0;
    for (int i = 0; i < 6000 && f.state() != tn::FollowState::kArrived; ++i) {
      const thorvald_base::Twist2D c = f.step(pose, 0.05);
      actual.vx += 0.5 * (c.vx - actual.vx);
      actual.wz += 0.5 * (c.wz - actual.wz);
      pose = pose * thorvald_base::Pose2D{actual.vx * 0.05, 0.0, actual.wz * 0.05};
      driven += std::abs(actual.vx) * 0.05;
    }
    if (f.state() != tn::FollowState::kArrived) continue;
    ++r.reached;
    r.err_xy.push_back(std::hypot(pose.x - goal.x, pose.y - goal.y));
    r.err_yaw.push_back(std::abs(thorvald_base::normalizeAngle(pose.yaw - goal.yaw)));
    if (plan.length_m > 0.05) r.ratio.push_back(driven / plan.length_m);
  }
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Localisation and navigation on synthetic headlands (kinematic robot, not MuJoCo)"};
  double seconds = 600.0;
  int goals = 50;
  std::uint32_t seed = 1;
  app.add_option("--seconds", seconds, "simulated driving time for localisation [s]")->check(CLI::Range(1.0, 7200.0));
  app.add_option("--goals", goals, "random navigation goals")->check(CLI::Range(1, 10000));
  app.add_option("--seed", seed, "seed of the headland and the noise");
  if (const auto code = thorvald_common::parseCommandLine(app, argc, argv)) return *code;

  std::printf("localisation: %.0f s of driving, 40 Hz scans, 2.5 cm map ...\n", seconds);
  std::fflush(stdout);
  const LocResult l = localise(seed, seconds);
  std::printf("  scans %d  rms %.4f m  rms yaw %.5f rad  %.3f ms/scan -> %.1f %% of one core at 40 Hz\n", l.scans,
              l.rms_xy, l.rms_yaw, l.ms_per_scan, l.ms_per_scan * 40.0 / 10.0);
  std::printf("navigation: %d random goals ...\n", goals);
  std::fflush(stdout);
  const NavResult n = navigate(seed, goals);
  const double success = 100.0 * n.reached / std::max(1, n.goals);
  std::printf("  reached %d of %d  p95 error %.4f m  %.4f rad  path ratio median %.3f\n", n.reached, n.goals,
              percentile(n.err_xy, 0.95), percentile(n.err_yaw, 0.95), percentile(n.ratio, 0.5));
  std::printf(
      "RESULT {\"world\": \"synthetic_kinematic\", \"loc_rms_m\": %.4f, \"loc_rms_yaw_rad\": %.5f, "
      "\"map_localizer_cpu_pct_40hz\": %.2f, \"nav_success_pct\": %.1f, \"nav_goal_err_m_p95\": %.4f, "
      "\"nav_goal_err_yaw_rad_p95\": %.4f, \"nav_path_ratio\": %.3f, \"goals\": %d}\n",
      l.rms_xy, l.rms_yaw, l.ms_per_scan * 4.0, success, percentile(n.err_xy, 0.95), percentile(n.err_yaw, 0.95),
      percentile(n.ratio, 0.5), n.goals);
  return 0;
}
