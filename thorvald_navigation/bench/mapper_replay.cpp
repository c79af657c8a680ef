// Replays a recorded mapping drive through the headland mapper (OccupancyMapper) outside ROS, scan by scan and
// deterministically, and traces its pose against a reference odometry topic recorded beside it (the simulator's
// ground_truth/odom, or a motion-capture system's). The reference is only read to score: the mapper sees the scans
// and tf, as the node does. Prints one line per integrated scan (or every --every-s seconds), the error statistics
// and a RESULT line; writes the map (map_server YAML + PGM) with --map-out.
//
//   rosbag record -O drive.bag /clock /tf /tf_static /thorvald_001/scan /thorvald_001/ground_truth/odom
//   rosrun thorvald_navigation mapper_replay --bag drive.bag --scan /thorvald_001/scan
//     --truth /thorvald_001/ground_truth/odom --config $(rospack find thorvald_navigation)/config/headland_mapper.yaml
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <thorvald_common/bench_statistics.h>
#include <thorvald_common/command_line.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2/buffer_core.h>
#include <tf2/exceptions.h>
#include <tf2_msgs/TFMessage.h>
#include <yaml-cpp/yaml.h>

#include "../src/nodes/ros_conversions.h"
#include "thorvald_map/map_file.h"
#include "thorvald_navigation/occupancy_mapper.h"

namespace tn = thorvald_navigation;

namespace {

struct Stamped {
  double t;
  thorvald_base::Pose2D pose;
};

/// Reference pose at time t by linear interpolation; false outside the recorded span.
bool interpolate(const std::vector<Stamped>& track, double t, thorvald_base::Pose2D* out) {
  if (track.empty() || t < track.front().t || t > track.back().t) return false;
  auto it = std::lower_bound(track.begin(), track.end(), t, [](const Stamped& s, double v) { return s.t < v; });
  if (it == track.begin()) {
    *out = it->pose;
    return true;
  }
  const Stamped& b = *it;
  const Stamped& a = *(it - 1);
  const double f = b.t > a.t ? (t - a.t) / (b.t - a.t) : 0.0;
  out->x = a.pose.x + f * (b.pose.x - a.pose.x);
  out->y = a.pose.y + f * (b.pose.y - a.pose.y);
  out->yaw = thorvald_base::normalizeAngle(a.pose.yaw + f * thorvald_base::normalizeAngle(b.pose.yaw - a.pose.yaw));
  return true;
}

/// Mapper parameters from a headland_mapper YAML (the node's names for the keys this replay uses).
void readConfig(const std::string& path, tn::MapperParams* m) {
  const YAML::Node y = YAML::LoadFile(path);
  auto num = [&](const char* key, double* v) {
    if (y[key]) *v = y[key].as<double>();
  };
  num("delta", &m->resolution_m);
  num("maxUrange", &m->max_range_m);
  num("linearUpdate", &m->linear_update_m);
  num("angularUpdate", &m->angular_update_rad);
  num("initial_size", &m->initial_size_m);
  num("max_size", &m->max_size_m);
  num("sigma", &m->matcher.sigma_hit_m);
  num("min_inlier_fraction", &m->min_inlier_fraction);
  num("odom_sigma_xy", &m->odom_sigma_xy_m);
  num("odom_sigma_yaw", &m->odom_sigma_yaw_rad);
  num("odom_sigma_fraction", &m->odom_sigma_fraction);
  num("surfel_half_length", &m->surfel_half_length_m);
  num("grazing_keep_max", &m->grazing_keep_max_m);
  num("grazing_neighbour_gap", &m->grazing_neighbour_gap_m);
  if (y["match_surface"]) m->match_surface = y["match_surface"].as<bool>();
  if (y["no_return_keeps_ends"]) m->no_return_keeps_ends = y["no_return_keeps_ends"].as<bool>();
}

using thorvald_common::percentile;

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Replays a recorded drive through the headland mapper and traces its pose against a reference"};
  std::string bag_path, scan_topic = "/thorvald_001/scan", truth_topic = "/thorvald_001/ground_truth/odom";
  std::string config, map_out, odom_frame = "thorvald_001/odom", base_frame = "thorvald_001/base_link";
  double every_s = 0.0;
  bool quiet = false;
  tn::MapperParams params;
  app.add_option("--bag", bag_path, "the recorded drive")->required()->check(CLI::ExistingFile);
  app.add_option("--scan", scan_topic, "LaserScan topic");
  app.add_option("--truth", truth_topic, "reference nav_msgs/Odometry topic; empty: no scoring");
  app.add_option("--config", config, "headland_mapper YAML (delta, maxUrange, odom_sigma_xy, ...)")
      ->check(CLI::ExistingFile);
  app.add_option("--odom-frame", odom_frame, "odometry frame on tf");
  app.add_option("--base-frame", base_frame, "robot frame on tf");
  app.add_option("--map-out", map_out, "write the map to STEM.yaml/STEM.pgm");
  app.add_option("--every", every_s, "print the trace every this many seconds (0: every integrated scan)");
  app.add_option("--odom-sigma-xy", params.odom_sigma_xy_m, "override the odometry prior [m]");
  app.add_option("--odom-sigma-fraction", params.odom_sigma_fraction, "override the prior's growth with motion");
  double grazing_keep_max = -1.0;
  app.add_option("--grazing-keep-max", grazing_keep_max,
                 "override grazing_keep_max (0: grazing beams clear as any) [m]");
  bool no_return_clears = false;
  app.add_flag("--no-return-clears", no_return_clears, "beams without a return clear cells where beams ended too");
  bool cell_centres = false, surface = false;
  app.add_flag("--cell-centres", cell_centres, "match at wall cell centres (match_surface false)");
  app.add_flag("--match-surface", surface, "match at the walls' surface (match_surface true)");
  app.add_flag("--quiet", quiet, "no trace, only the summary");
  if (const auto code = thorvald_common::parseCommandLine(app, argc, argv)) return *code;
  // Config first, then the command line's overrides win.
  tn::MapperParams defaults;
  if (!config.empty()) {
    const tn::MapperParams cli = params;
    params = defaults;
    readConfig(config, &params);
    if (cli.odom_sigma_xy_m != defaults.odom_sigma_xy_m) params.odom_sigma_xy_m = cli.odom_sigma_xy_m;
    if (cli.odom_sigma_fraction != defaults.odom_sigma_fraction) params.odom_sigma_fraction = cli.odom_sigma_fraction;
  }
  if (grazing_keep_max >= 0.0) params.grazing_keep_max_m = grazing_keep_max;
  if (no_return_clears) params.no_return_keeps_ends = false;
  if (cell_centres) params.match_surface = false;
  if (surface) params.match_surface = true;
  const std::string problem = params.validate();
  if (!problem.empty()) {
    std::fprintf(stderr, "mapper_replay: %s\n", problem.c_str());
    return 2;
  }

  rosbag::Bag bag;
  try {
    bag.open(bag_path, rosbag::bagmode::Read);
  } catch (const rosbag::BagException& e) {
    std::fprintf(stderr, "mapper_replay: cannot open %s: %s\n", bag_path.c_str(), e.what());
    return 2;
  }
  // Pass 1: tf (whole drive) and the reference track.
  tf2::BufferCore tf(ros::Duration(1e5));
  std::vector<Stamped> truth;
  {
    rosbag::View view(bag, rosbag::TopicQuery(std::vector<std::string>{"/tf", "/tf_static", truth_topic}));
    for (const rosbag::MessageInstance& m : view) {
      if (auto t = m.instantiate<tf2_msgs::TFMessage>()) {
        const bool is_static = m.getTopic() == "/tf_static";
        for (const auto& tr : t->transforms) tf.setTransform(tr, "bag", is_static);
      } else if (auto o = m.instantiate<nav_msgs::Odometry>()) {
        truth.push_back({o->header.stamp.toSec(), thorvald_map::fromPose(o->pose.pose)});
      }
    }
  }
  std::sort(truth.begin(), truth.end(), [](const Stamped& a, const Stamped& b) { return a.t < b.t; });
  if (!truth_topic.empty() && truth.empty())
    std::fprintf(stderr, "mapper_replay: no messages on %s; the trace is not scored\n", truth_topic.c_str());

  tn::OccupancyMapper mapper(params);
  bool have_origin = false;
  thorvald_base::Pose2D truth_origin;  // the reference pose at the first integrated scan: the map frame's origin
  std::vector<double> err_xy, err_along, err_across, err_yaw, odom_err_xy;
  int scans = 0, skipped = 0, integrated = 0, unmatched = 0;
  double t0 = -1.0, next_print = 0.0;
  thorvald_base::Pose2D sensor;
  bool have_sensor = false;
  if (!quiet)
    std::printf("%8s %9s %9s %8s %9s %9s %8s %9s %9s %8s %6s\n", "t s", "map x", "map y", "yaw", "err x", "err y",
                "err yaw", "odom ex", "odom ey", "inliers", "match");
  rosbag::View scans_view(bag, rosbag::TopicQuery(scan_topic));
  for (const rosbag::MessageInstance& m : scans_view) {
    const auto scan = m.instantiate<sensor_msgs::LaserScan>();
    if (!scan) continue;
    ++scans;
    try {
      if (!have_sensor) {
        sensor =
            thorvald_map::fromTransform(tf.lookupTransform(base_frame, scan->header.frame_id, ros::Time(0)).transform);
        have_sensor = true;
      }
      const thorvald_base::Pose2D odom =
          thorvald_map::fromTransform(tf.lookupTransform(odom_frame, base_frame, scan->header.stamp).transform);
      tn::ScanPoints pts;
      const std::string e = tn::scanToPoints(*scan, sensor, params.max_range_m, &pts);
      if (!e.empty()) {
        ++skipped;
        continue;
      }
      const tn::MapperUpdate u = mapper.addScan(odom, {sensor.x, sensor.y}, pts.hits, pts.free_ends);
      if (!u.integrated) continue;
      ++integrated;
      unmatched += u.matched || integrated == 1 ? 0 : 1;
      const double t = scan->header.stamp.toSec();
      if (t0 < 0.0) t0 = t;
      thorvald_base::Pose2D ref;
      const bool scored = interpolate(truth, t, &ref);
      if (scored && !have_origin) {
        // The map frame is the odometry pose of the first scan; the reference at that moment is its origin.
        truth_origin = ref * odom.inverse();
        have_origin = true;
      }
      double ex = 0.0, ey = 0.0, eyaw = 0.0, oex = 0.0, oey = 0.0;
      if (scored && have_origin) {
        const thorvald_base::Pose2D r = truth_origin.inverse() * ref;
        oex = odom.x - r.x;  // odometry alone, in the same frame (the map frame starts on the odometry)
        oey = odom.y - r.y;
        odom_err_xy.push_back(std::hypot(oex, oey));
        ex = u.pose.x - r.x;
        ey = u.pose.y - r.y;
        eyaw = thorvald_base::normalizeAngle(u.pose.yaw - r.yaw);
        err_xy.push_back(std::hypot(ex, ey));
        err_along.push_back(std::abs(ex));
        err_across.push_back(std::abs(ey));
        err_yaw.push_back(std::abs(eyaw));
      }
      if (!quiet && t - t0 >= next_print) {
        std::printf("%8.2f %9.4f %9.4f %8.4f %9.4f %9.4f %8.4f %9.4f %9.4f %8.3f %6s\n", t - t0, u.pose.x, u.pose.y,
                    u.pose.yaw, ex, ey, eyaw, oex, oey, u.inlier_fraction, u.matched ? "yes" : "no");
        next_print = every_s > 0.0 ? t - t0 + every_s : 0.0;
      }
    } catch (const tf2::TransformException& e) {
      ++skipped;
    }
  }
  bag.close();
  if (!map_out.empty()) {
    thorvald_map::OccupancyGrid map = mapper.occupancyGrid();
    map.surface = mapper.wallSurface();
    std::string e;
    if (!thorvald_map::saveMap(map, map_out, &e)) std::fprintf(stderr, "mapper_replay: %s\n", e.c_str());
  }
  const double end_xy = err_xy.empty() ? 0.0 : err_xy.back();
  std::printf("scans %d, integrated %d, unmatched %d, skipped (no tf / bad scan) %d\n", scans, integrated, unmatched,
              skipped);
  if (!err_xy.empty())
    std::printf(
        "error vs reference: xy mean %.4f p95 %.4f max %.4f end %.4f m; |x| p95 %.4f |y| p95 %.4f m; "
        "yaw p95 %.4f rad\n",
        std::accumulate(err_xy.begin(), err_xy.end(), 0.0) / err_xy.size(), percentile(err_xy, 0.95),
        percentile(err_xy, 1.0), end_xy, percentile(err_along, 0.95), percentile(err_across, 0.95),
        percentile(err_yaw, 0.95));
  if (!odom_err_xy.empty())
    std::printf("odometry alone vs reference: xy p95 %.4f max %.4f end %.4f m\n", percentile(odom_err_xy, 0.95),
                percentile(odom_err_xy, 1.0), odom_err_xy.back());
  std::printf(
      "RESULT {\"scans_integrated\": %d, \"unmatched\": %d, \"err_xy_p95_m\": %.4f, \"err_xy_max_m\": %.4f, "
      "\"err_x_p95_m\": %.4f, \"err_y_p95_m\": %.4f, \"err_yaw_p95_rad\": %.4f}\n",
      integrated, unmatched, percentile(err_xy, 0.95), percentile(err_xy, 1.0), percentile(err_along, 0.95),
      percentile(err_across, 0.95), percentile(err_yaw, 0.95));
  return integrated > 0 ? 0 : 1;
}
