// boll_dataset_export: camera frames of the simulated cotton row in its `datasheet` realism with the truth of every
// boll and of the end-effector, for training and scoring the boll network (cotton_harvester/training, models/).
//
// One rover simulation per seed in [--seed-begin, --seed-end): the seed draws the row (plants, leaves, leaves over
// bolls, slope, boll size), the camera height (1.9-2.5 m) and where the camera stands over the row; each of its
// --frames-per-sim frames draws the day (sunny 60 % or overcast, sun elevation 25-75 deg, any azimuth, exposure
// 0.7-1.35) and where the arm is. Each frame writes
//   images/<name>.png   the colour frame, resized to --width x --height (0 0: kept at 1280x720) with an
//                       interpolation drawn per frame (area, linear or nearest) unless --full
//   labels/<name>.txt   YOLO labels: `class cx cy w h` normalised to the image, class 0 boll, 1 end-effector; a boll
//                       is labelled when its centre is in view and at least --min-visible of its disc is seen
//                       in the frame's true depth
//   truth/<name>.txt    the day (`day sunny|overcast exposure`), every boll in view (`boll u v radius_px visible
//                       x y z ray_visible`: camera frame [m], its centre; visible from the true depth, ray_visible
//                       the simulator's ray test) and the end-effector's top face (`end_effector u v visible x y z`);
//                       pixels at 1280x720
//   depth/<name>.png    with --full: the frame's depth along the optical axis, 16-bit millimetres (0: none)
// Held-out seeds are never used for training: see cotton_harvester/models/README.md.
//   rosrun cotton_harvester_sim boll_dataset_export --out DIR [--seed-begin 1000] [--seed-end 1100]
//          [--frames-per-sim 4] [--width 448 --height 256] [--min-visible 0.3] [--full]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <thorvald_common/command_line.h>

#include "cotton_harvester_sim/harvest_run.h"

namespace fs = std::filesystem;
using cotton_harvester::sim::RoverSim;
using cotton_harvester::sim::RoverSimParams;

namespace {

struct ExportOptions {
  std::string out;
  unsigned seed_begin = 1000, seed_end = 1100;
  int frames_per_sim = 4;
  int width = 448, height = 256;
  double min_visible = 0.3;
  bool full = false;
};

double uniform(std::mt19937& rng, double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng); }

/// The row and the rover of one seed: a short datasheet row (4-6 plants), defoliated to undefoliated, the camera
/// 1.9-2.5 m above the ground somewhere over the plants.
RoverSimParams simParams(unsigned seed) {
  std::mt19937 rng(seed * 2654435761u + 11u);
  RoverSimParams p = cotton_harvester::sim::pottedConfig(seed).sim;
  p.realism = thorvald_sim::Realism::kDatasheet;
  p.row.plants = 4 + static_cast<int>(rng() % 3);
  p.row.leaves_per_plant = 3 + static_cast<int>(rng() % 11);
  p.row.leaf_over_boll_fraction = uniform(rng, 0.0, 0.45);
  p.row.slope_deg = uniform(rng, 0.0, 3.0);
  p.row.boll_radius_m = uniform(rng, 0.03, 0.042);
  p.row.bolls_per_plant = 2 + static_cast<int>(rng() % 3);
  p.geometry.camera_height_m = uniform(rng, 1.9, 2.5);
  p.geometry.max_depth_m = p.geometry.camera_height_m - 0.27;
  const double along = uniform(rng, -0.15, (p.row.plants - 1) * p.row.plant_spacing_m + 0.15);
  p.start_x_m = p.row.first_plant_x_m + along - p.geometry.camera_ahead_m;
  return p;
}

thorvald_sim::Daylight drawDay(std::mt19937& rng) {
  const double elevation = uniform(rng, 25.0, 75.0) * M_PI / 180.0, azimuth = uniform(rng, -M_PI, M_PI);
  const bool sunny = uniform(rng, 0.0, 1.0) < 0.6;
  thorvald_sim::Daylight day =
      sunny ? thorvald_sim::sunnyDaylight(elevation, azimuth) : thorvald_sim::overcastDaylight(elevation, azimuth);
  day.exposure = uniform(rng, 0.7, 1.35);
  return day;
}

struct Projector {
  double fx, cx, cy;
  cv::Point2d operator()(const Eigen::Vector3d& c) const { return {fx * c.x() / c.z() + cx, fx * c.y() / c.z() + cy}; }
};

/// Writes the YOLO label of a box [px] in an image of `size`; false when nothing of it is in the image.
bool writeLabel(std::ofstream& out, int cls, cv::Rect2d box, const cv::Size& size) {
  box &= cv::Rect2d(0, 0, size.width, size.height);
  if (box.width < 1.0 || box.height < 1.0) return false;
  char line[128];
  std::snprintf(line, sizeof(line), "%d %.6f %.6f %.6f %.6f\n", cls, (box.x + 0.5 * box.width) / size.width,
                (box.y + 0.5 * box.height) / size.height, box.width / size.width, box.height / size.height);
  out << line;
  return true;
}

/// The end-effector housing's image box [px]: the bounding box of its eight corners (a box hanging below its top
/// face, axes taken as the world's).
cv::Rect2d housingBox(const RoverSim& sim, const Projector& project) {
  const auto& g = sim.params().geometry;
  const Eigen::Vector3d top = sim.nozzlePosition() + Eigen::Vector3d(0, 0, 0.5 * g.effector_height_m);
  double u0 = 1e9, v0 = 1e9, u1 = -1e9, v1 = -1e9;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3d corner =
        top + Eigen::Vector3d((k & 1 ? 1 : -1) * g.effector_half_m, (k & 2 ? 1 : -1) * g.effector_half_m,
                              (k & 4) ? -g.effector_height_m : 0.0);
    const Eigen::Vector3d c = sim.toCamera(corner);
    if (c.z() <= 0.05) return {};
    const cv::Point2d px = project(c);
    u0 = std::min(u0, px.x), v0 = std::min(v0, px.y), u1 = std::max(u1, px.x), v1 = std::max(v1, px.y);
  }
  return {u0, v0, u1 - u0, v1 - v0};
}

/// Share of the boll's disc (points within 0.8 of its projected radius) whose true depth in the last frame lies on
/// the boll (within 1.2 radii of its centre's depth): what the camera really sees of it [0, 1]. The simulator's own
/// ray test (bollVisibleFraction, 9 rays) is written beside it.
double depthVisibleFraction(const RoverSim& sim, const cv::Point2d& px, double r_px, double z, double r_m) {
  const std::vector<float>& depth = sim.lastTrueDepth();
  const int w = sim.params().camera_width, h = sim.params().camera_height;
  int on = 0, all = 0;
  const double step = std::max(1.0, 0.2 * r_px);
  for (double dv = -0.8 * r_px; dv <= 0.8 * r_px; dv += step)
    for (double du = -0.8 * r_px; du <= 0.8 * r_px; du += step) {
      if (du * du + dv * dv > 0.64 * r_px * r_px) continue;
      ++all;
      const int u = static_cast<int>(std::lround(px.x + du)), v = static_cast<int>(std::lround(px.y + dv));
      if (u < 0 || v < 0 || u >= w || v >= h || depth.size() != static_cast<size_t>(w) * h) continue;
      const float d = depth[static_cast<size_t>(v) * w + u];
      on += std::isfinite(d) && std::abs(d - z) <= 1.2 * r_m ? 1 : 0;
    }
  return all > 0 ? static_cast<double>(on) / all : 0.0;
}

/// Labels and truth of the frame just rendered; returns the number of bolls labelled.
int writeTruth(RoverSim& sim, const ExportOptions& o, const std::string& name, const cv::Size& size) {
  const RoverSimParams& p = sim.params();
  const Projector project{p.fx, p.cx, p.cy};
  const double scale_x = static_cast<double>(size.width) / p.camera_width;
  const double scale_y = static_cast<double>(size.height) / p.camera_height;
  std::ofstream labels(o.out + "/labels/" + name + ".txt"), truth(o.out + "/truth/" + name + ".txt");
  truth << "day " << (sim.daylight().sunny ? "sunny" : "overcast") << " " << sim.daylight().exposure << "\n";
  int labelled = 0;
  for (size_t i = 0; i < sim.bolls().size(); ++i) {
    const auto& b = sim.bolls()[i];
    if (b.captured || !sim.bollInView(i)) continue;
    const Eigen::Vector3d c = sim.toCamera(b.centre);
    const cv::Point2d px = project(c);
    const double r_px = p.fx * p.row.boll_radius_m / c.z();
    const double visible = depthVisibleFraction(sim, px, r_px, c.z(), p.row.boll_radius_m);
    char line[200];
    std::snprintf(line, sizeof(line), "boll %.2f %.2f %.2f %.3f %.4f %.4f %.4f %.3f\n", px.x, px.y, r_px, visible,
                  c.x(), c.y(), c.z(), sim.bollVisibleFraction(i));
    truth << line;
    if (visible < o.min_visible) continue;
    const cv::Rect2d box((px.x - r_px) * scale_x, (px.y - r_px) * scale_y, 2 * r_px * scale_x, 2 * r_px * scale_y);
    labelled += writeLabel(labels, 0, box, size) ? 1 : 0;
  }
  const cv::Rect2d housing = housingBox(sim, project);
  const Eigen::Vector3d top =
      sim.toCamera(sim.nozzlePosition() + Eigen::Vector3d(0, 0, 0.5 * p.geometry.effector_height_m));
  const cv::Point2d top_px = project(top);
  const bool in_view =
      housing.area() > 0 && top_px.x >= 0 && top_px.y >= 0 && top_px.x < p.camera_width && top_px.y < p.camera_height;
  if (in_view) {
    const cv::Rect2d box(housing.x * scale_x, housing.y * scale_y, housing.width * scale_x, housing.height * scale_y);
    writeLabel(labels, 1, box, size);
    char line[200];
    std::snprintf(line, sizeof(line), "end_effector %.2f %.2f 1.0 %.4f %.4f %.4f\n", top_px.x, top_px.y, top.x(),
                  top.y(), top.z());
    truth << line;
  }
  return labelled;
}

void writeDepth(const cv::Mat& cloud, const std::string& path) {
  cv::Mat mm(cloud.rows, cloud.cols, CV_16UC1, cv::Scalar(0));
  for (int v = 0; v < cloud.rows; ++v)
    for (int u = 0; u < cloud.cols; ++u) {
      const float z = cloud.at<cv::Vec3f>(v, u)[2];
      if (std::isfinite(z) && z > 0.0f && z < 65.0f)
        mm.at<uint16_t>(v, u) = static_cast<uint16_t>(std::lround(z * 1e3));
    }
  cv::imwrite(path, mm);
}

/// Renders the frames of one seed; returns the number of frames written.
int exportSeed(unsigned seed, const ExportOptions& o, int* bolls) {
  RoverSim sim(simParams(seed));
  std::mt19937 rng(seed * 40503u + 7u);
  const int interpolations[3] = {cv::INTER_AREA, cv::INTER_LINEAR, cv::INTER_NEAREST};
  for (int k = 0; k < o.frames_per_sim; ++k) {
    sim.setDaylight(drawDay(rng));
    sim.commandHorizontal(uniform(rng, 0.0, sim.params().geometry.horizontal_travel_m));
    sim.commandVertical(uniform(rng, sim.params().geometry.min_depth_m, 1.1));
    sim.advance(k == 0 ? 2.0 : 1.0);
    cv::Mat bgr, cloud, out;
    sim.renderCamera(&bgr, &cloud);
    const std::string name = "s" + std::to_string(seed) + "_" + std::to_string(k);
    if (o.full || o.width <= 0) {
      out = bgr;
    } else {
      cv::resize(bgr, out, cv::Size(o.width, o.height), 0, 0, interpolations[rng() % 3]);
    }
    cv::imwrite(o.out + "/images/" + name + ".png", out);
    if (o.full) writeDepth(cloud, o.out + "/depth/" + name + ".png");
    *bolls += writeTruth(sim, o, name, out.size());
  }
  return o.frames_per_sim;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Renders labelled datasheet frames of the simulated cotton row for the boll network"};
  ExportOptions o;
  app.add_option("--out", o.out, "output folder (images/, labels/, truth/, depth/)")->required();
  app.add_option("--seed-begin", o.seed_begin, "first seed");
  app.add_option("--seed-end", o.seed_end, "one past the last seed");
  app.add_option("--frames-per-sim", o.frames_per_sim, "frames per seed")->check(CLI::Range(1, 50));
  app.add_option("--width", o.width, "image width written (0: 1280x720 kept)");
  app.add_option("--height", o.height, "image height written");
  app.add_option("--min-visible", o.min_visible, "label a boll when this share of it is visible")
      ->check(CLI::Range(0.0, 1.0));
  app.add_flag("--full", o.full, "held-out frames: 1280x720 colour and 16-bit depth");
  if (const auto code = thorvald_common::parseCommandLine(app, argc, argv)) return *code;
  for (const char* sub : {"images", "labels", "truth", "depth"}) fs::create_directories(o.out + "/" + sub);
  int frames = 0, bolls = 0;
  const auto start = std::chrono::steady_clock::now();
  for (unsigned seed = o.seed_begin; seed < o.seed_end; ++seed) {
    try {
      frames += exportSeed(seed, o, &bolls);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "seed %u: %s\n", seed, e.what());
    }
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("seed %u: %d frames, %d labelled bolls, %.1f s\n", seed, frames, bolls, s);
    std::fflush(stdout);
  }
  return frames > 0 ? 0 : 1;
}
