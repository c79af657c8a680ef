// Rail detection accuracy and speed on synthetic depth clouds with ground truth (paper Table I).
//   rosrun greenhouse_rail_nav rail_detection_bench [poses=500]
#include <algorithm>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "greenhouse_rail_nav/rail_detector.h"
#include "greenhouse_rail_nav/synthetic_depth_cloud.h"

using greenhouse_rail_nav::DepthSceneParams;
using greenhouse_rail_nav::normalizeAngle;
using greenhouse_rail_nav::Pose2D;
using greenhouse_rail_nav::RailDetection;
using greenhouse_rail_nav::RailDetector;
using greenhouse_rail_nav::RailDetectorParams;
using greenhouse_rail_nav::RailFitMethod;

namespace {

struct Errors {
  int tried = 0, found = 0;
  double sx = 0, sy = 0, syaw = 0, max_x = 0, max_y = 0, max_yaw = 0;
  void add(const Pose2D& truth, const RailDetection& d) {
    ++tried;
    if (!d.found()) return;
    ++found;
    const double ex = d.base_in_rail.x - truth.x, ey = d.base_in_rail.y - truth.y;
    const double eyaw = normalizeAngle(d.base_in_rail.yaw - truth.yaw);
    sx += ex * ex;
    sy += ey * ey;
    syaw += eyaw * eyaw;
    max_x = std::max(max_x, std::abs(ex));
    max_y = std::max(max_y, std::abs(ey));
    max_yaw = std::max(max_yaw, std::abs(eyaw));
  }
  void merge(const Errors& o) {
    tried += o.tried;
    found += o.found;
    sx += o.sx;
    sy += o.sy;
    syaw += o.syaw;
    max_x = std::max(max_x, o.max_x);
    max_y = std::max(max_y, o.max_y);
    max_yaw = std::max(max_yaw, o.max_yaw);
  }
  double rms(double s) const { return found ? std::sqrt(s / found) : NAN; }
  double notFoundPct() const { return tried ? 100.0 * (tried - found) / tried : 0.0; }
  void print(const char* method, const char* set) const {
    std::printf("%-22s %-10s %5d %8.1f %8.4f %8.4f %9.4f %8.4f %8.4f %9.4f\n", method, set, tried, notFoundPct(),
                rms(sx), rms(sy), rms(syaw), max_x, max_y, max_yaw);
  }
};

/// CPU time of this thread [ms]: the figure for "one core", unaffected by other processes on the machine.
double threadMs() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

}  // namespace

int main(int argc, char** argv) {
  const int poses = argc > 1 ? std::max(2, std::atoi(argv[1])) : 500;
  const RailDetectorParams params;
  const RailDetector detector(params);
  DepthSceneParams scene;
  std::mt19937 rng(2024);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);

  // Half the poses in the ranges of the paper's Table I, half wider.
  Errors ours[2], baseline[2];
  double detect_ms = 0.0;
  for (int i = 0; i < poses; ++i) {
    const int set = i % 2;
    Pose2D truth;
    if (set == 0) {
      truth = Pose2D(-0.71 + 0.11 * unit(rng), 0.09 * unit(rng), 0.045 * unit(rng));
    } else {
      truth = Pose2D(-0.85 + 0.45 * unit(rng), 0.35 * unit(rng), 0.35 * unit(rng));
    }
    scene.seed = 1000 + static_cast<std::uint32_t>(i);
    const auto cloud = greenhouse_rail_nav::renderDepthCloud(scene, truth);
    const double t0 = threadMs();
    const auto found = detector.detect(cloud, scene.camera_in_base);
    detect_ms += (threadMs() - t0);
    ours[set].add(truth, found);
    baseline[set].add(truth, detector.detect(cloud, scene.camera_in_base, Pose2D(), RailFitMethod::kRansacBaseline));
  }
  Errors ours_all, base_all;
  for (int s = 0; s < 2; ++s) {
    ours_all.merge(ours[s]);
    base_all.merge(baseline[s]);
  }
  std::printf("Rail detection, %d random poses (640x480 synthetic active-stereo clouds)\n", poses);
  std::printf(
      "  'table I': x in [-0.82,-0.60] m, |y| <= 0.09 m, |yaw| <= 0.045 rad; 'wide': x in [-1.3,-0.4] m,"
      " |y| <= 0.35 m, |yaw| <= 0.35 rad\n\n");
  std::printf("%-22s %-10s %5s %8s %8s %8s %9s %8s %8s %9s\n", "method", "poses", "n", "miss[%]", "rms_x", "rms_y",
              "rms_yaw", "max_x", "max_y", "max_yaw");
  ours[0].print("clusters+LSQ (paper)", "table I");
  ours[1].print("clusters+LSQ (paper)", "wide");
  ours_all.print("clusters+LSQ (paper)", "all");
  baseline[0].print("PCL RANSAC lines", "table I");
  baseline[1].print("PCL RANSAC lines", "wide");
  base_all.print("PCL RANSAC lines", "all");
  std::printf("%-22s %-10s %5d %8s %8.4f %8.4f %9.4f %8.4f %8.4f %9.4f\n", "paper Table I (real)", "table I", 12, "-",
              0.11, 0.02, 0.014, 0.24, 0.04, 0.032);

  // Time per cloud against cloud size (same field of view), one core.
  std::printf(
      "\nThread CPU time per cloud (detection only: transform, crop, thin, cluster, fit), frame period 33.3 ms\n");
  std::printf("%-12s %10s %12s %10s\n", "cloud", "points", "ms/cloud", "x period");
  double ms_640 = 0.0;
  const std::vector<std::pair<int, int>> sizes = {{160, 120}, {320, 240}, {640, 480}, {1280, 960}};
  for (const auto& [w, h] : sizes) {
    DepthSceneParams sized = scene;
    sized.intrinsics = scene.intrinsics.scaled(w, h);
    const int runs = w >= 1280 ? 5 : 20;
    double total = 0.0;
    for (int r = 0; r < runs; ++r) {
      sized.seed = 500 + static_cast<std::uint32_t>(r);
      const auto cloud = greenhouse_rail_nav::renderDepthCloud(sized, Pose2D(-0.75, 0.02 * (r % 5), 0.01));
      const double t0 = threadMs();
      const auto d = detector.detect(cloud, sized.camera_in_base);
      total += (threadMs() - t0);
      (void)d;
    }
    const double ms = total / runs;
    if (w == 640) ms_640 = ms;
    std::printf("%4dx%-7d %10d %12.2f %10.2f\n", w, h, w * h, ms, ms / 33.3);
  }
  std::printf("\nmean over the accuracy run (640x480): %.2f ms/cloud\n", detect_ms / poses);
  std::printf(
      "RESULT {\"rms_x_m\": %.4f, \"rms_y_m\": %.4f, \"rms_yaw_rad\": %.4f, \"max_y_m\": %.4f, "
      "\"not_found_pct\": %.2f, \"baseline_rms_y_m\": %.4f, \"baseline_rms_yaw_rad\": %.4f, "
      "\"ms_per_cloud_640x480\": %.2f}\n",
      ours_all.rms(ours_all.sx), ours_all.rms(ours_all.sy), ours_all.rms(ours_all.syaw), ours_all.max_y,
      ours_all.notFoundPct(), base_all.rms(base_all.sy), base_all.rms(base_all.syaw), ms_640);
  return 0;
}
