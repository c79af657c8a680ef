// perception_bench: time per 720p frame of the colour pipeline (single OpenCV thread) and of the tiny-YOLOv3 path,
// and detection precision/recall, 3D error and end-effector detection of the colour pipeline on synthetic frames
// with ground truth: sun, overcast and shade, random exposure and white balance, glare on the end-effector, touching
// boll clusters, leaves over bolls, at 1280x720 and at 640x360 and 1920x1080.
// The trained boll network (detector: network): its time per 720p frame (ms_per_frame_dnn, single thread), whether
// its weights detect (network_trained), and with --heldout-dir its precision and recall next to the colour
// detector's on held-out datasheet frames of the simulated row (cotton_harvester_sim's boll_dataset_export --full,
// seeds never trained on), with --fig8 also with bilinear, nearest and no interpolation of its input (paper Fig. 8).
//   rosrun cotton_harvester perception_bench [--frames N] [--other-resolution-frames N] [--dnn-frames N] [--seed S]
//                                            [--list-misses] [--network-model FILE] [--heldout-dir DIR] [--fig8]
//                                            [--gap] [--noise-curve N] [--noise-curve-network]
//                                            [--heldout-top-fraction F]
// --gap (with --heldout-dir): where the held-out bolls are lost between 2D and 3D, the 3D error along and across the
// ray, by share of the boll with depth, with and without the size fallback. --noise-curve N: recall and 3D error
// against passive-stereo depth noise on N synthetic frames a level. Held-out bolls are scored against their visible
// top, 0.6 radii in front of their centre (the datasheet boll; --heldout-top-fraction 1: a sphere's surface).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <cstdio>
#include <limits>
#include <filesystem>
#include <numeric>
#include <string>
#include <vector>

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <thorvald_common/command_line.h>
#include <opencv2/core/utility.hpp>
#include <thorvald_common/bench_statistics.h>

#include "cotton_harvester/perception/colour_boll_detector.h"
#include "cotton_harvester/perception/darknet_boll_detector.h"
#include "cotton_harvester/perception/perception_pipeline.h"
#include "cotton_harvester/testing/darknet_net_writer.h"
#include "cotton_harvester/testing/detection_scoring.h"
#include "cotton_harvester/testing/heldout_frames.h"
#include "cotton_harvester/testing/scene_renderer.h"
#include "network_figures.h"
#include "perception_bench_gap.h"

using namespace cotton_harvester::perception;
using Clock = std::chrono::steady_clock;

namespace {

struct Timing {
  std::vector<double> ms;
  double mean() const { return thorvald_common::mean(ms); }
  double percentile(double q) const { return thorvald_common::percentile(ms, q); }
};

template <typename F>
double timeMs(F&& f) {
  const auto start = Clock::now();
  f();
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

/// CPU time of this thread [ms]: the figure that holds on a machine shared with other work.
double threadCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}

double ratio(int part, int whole) { return whole > 0 ? static_cast<double>(part) / whole : 1.0; }

void printScores(const std::string& name, const ScoreSummary& s) {
  std::printf("%-26s %5d %5d %5d %9.3f %7.3f %10.4f %10.4f %7d/%-4d %6.3f %5d\n", name.c_str(), s.true_positives,
              s.false_positives, s.false_negatives, s.precision(), s.recall(), s.meanError3d(),
              s.percentileError3d(0.95), s.end_effector_found, s.end_effector_expected,
              ratio(s.end_effector_found, s.end_effector_expected), s.end_effector_false);
}

/// Why a boll may be hard: whole and alone, touching another boll in the image (split), or partly hidden.
enum BollCase { kWhole = 0, kTouching = 1, kPartlyHidden = 2 };
const char* const kCaseNames[] = {"whole, alone", "touching another boll", "partly hidden"};

BollCase caseOf(const SceneLayout& truth, size_t b) {
  const TrueBoll& boll = truth.bolls[b];
  for (size_t o = 0; o < truth.bolls.size(); ++o) {
    if (o == b || truth.bolls[o].visible_fraction <= 0.0) continue;
    const cv::Point2d d = truth.bolls[o].pixel - boll.pixel;
    if (std::hypot(d.x, d.y) <= boll.radius_px + truth.bolls[o].radius_px + 1.0) return kTouching;
  }
  return boll.visible_fraction >= 0.95 ? kWhole : kPartlyHidden;
}

/// Recall and 3D error per BollCase.
struct CaseStats {
  int found = 0, missed = 0;
  ScoreSummary errors;  ///< only errors_3d_m is used
  void add(const FrameScore& score, const SceneLayout& truth, BollCase which) {
    for (size_t i = 0; i < score.matched_bolls.size(); ++i) {
      if (caseOf(truth, score.matched_bolls[i]) != which) continue;
      ++found;
      errors.errors_3d_m.push_back(score.errors_3d_m[i]);
    }
    for (size_t b : score.missed_bolls) missed += caseOf(truth, b) == which;
  }
};

const Lighting kLightings[] = {Lighting::kSunny, Lighting::kCloudy, Lighting::kShade};

SceneParams sceneFor(int frame, const CameraIntrinsics& intrinsics) {
  SceneParams scene;
  scene.intrinsics = intrinsics;
  scene.lighting = kLightings[frame % 3];
  // Every fourth frame: a field-like, undefoliated canopy with more leaves over the bolls.
  if (frame % 4 == 3) {
    scene.leaves_per_plant = 34;
    scene.leaf_over_boll_probability = 0.5;
  }
  // Every other frame: white things that are not bolls (labels, bags, aluminium, large stones).
  if (frame % 2 == 1) scene.clutter_items = 3;
  // A camera a little higher or lower than the paper's 2.20 m (terrain, a re-mounted camera).
  scene.camera_height_m = 2.20 + 0.1 * ((frame % 5) - 2) / 2.0;
  return scene;
}

}  // namespace

int main(int argc, char** argv) {
  int frames = 150, other_frames = 45, dnn_frames = 20;
  std::uint32_t seed = 1;
  CLI::App app{"perception_bench: speed and accuracy of the boll and end-effector perception on synthetic frames"};
  app.add_option("--frames", frames, "1280x720 frames scored and timed")->check(CLI::Range(1, 100000));
  app.add_option("--other-resolution-frames", other_frames, "frames scored at 640x360 and at 1920x1080 each")
      ->check(CLI::Range(0, 100000));
  app.add_option("--dnn-frames", dnn_frames, "frames timed through the tiny-YOLOv3 path")->check(CLI::Range(0, 100000));
  app.add_option("--seed", seed, "first random seed");
  bool list_misses = false;
  app.add_flag("--list-misses", list_misses,
               "print every missed boll and every false detection of the colour pipeline (frame seed, size, pixel, "
               "case, visible share, nearest detection) to look at them one by one");
  NetworkParams network_params;
  std::string heldout_dir;
  bool fig8 = false;
  app.add_option("--network-model", network_params.model_path, "the boll network (default: the shipped ONNX)");
  app.add_option("--heldout-dir", heldout_dir, "held-out datasheet frames (boll_dataset_export --full) to score");
  app.add_flag("--fig8", fig8, "with --heldout-dir: the network with bilinear, nearest and no input interpolation");
  bool gap = false, noise_network = false;
  double top_fraction = kDatasheetBollTopFraction;
  app.add_option("--heldout-top-fraction", top_fraction,
                 "held-out truth: a boll's visible top lies this many radii in front of its centre (1: a sphere)")
      ->check(CLI::Range(0.0, 1.0));
  int noise_frames = 0;
  app.add_flag("--gap", gap, "with --heldout-dir: where bolls are lost between 2D and 3D, and the 3D error's parts");
  app.add_option("--noise-curve", noise_frames, "synthetic frames a level of the depth-noise curve (0: none)")
      ->check(CLI::Range(0, 10000));
  app.add_flag("--noise-curve-network", noise_network, "the depth-noise curve of the network too");
  if (const auto code = thorvald_common::parseCommandLine(app, argc, argv)) return *code;

  // The timing figure is single-core, as the goal states.
  cv::setNumThreads(1);

  // The tiny-YOLOv3-sized network (random weights: its detections mean nothing, its cost is the real one).
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("cotton_harvester_bench_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  DarknetParams darknet;
  darknet.cfg_path = (dir / "tiny_yolov3_boll.cfg").string();
  darknet.weights_path = (dir / "tiny_yolov3_boll.weights").string();
  writeDarknetFiles(tinyYoloV3Layout(416, 416, 1, seed), darknet.cfg_path, darknet.weights_path);

  struct Resolution {
    int width, height, frames;
  };
  const Resolution resolutions[] = {{1280, 720, frames}, {640, 360, other_frames}, {1920, 1080, other_frames}};

  ScoreSummary by_light[3], by_resolution[3], all, all_paper, all_rgb, all_window, all_no_partial, all_arc_test,
      all_no_dome;
  CaseStats by_case[3];
  Timing colour_time, colour_cpu, dnn_time, network_time, render_time;
  int total = 0;
  for (const Resolution& resolution : resolutions) total += resolution.frames;
  int done = 0;
  for (int r = 0; r < 3; ++r) {
    const Resolution& resolution = resolutions[r];
    PerceptionParams params;
    params.intrinsics = scaledTo(CameraIntrinsics{}, resolution.width, resolution.height);
    PerceptionPipeline colour(params, std::make_unique<ColourBollDetector>(ColourBollParams{}));
    PerceptionParams paper_params = params;
    paper_params.locator.depth_model = DepthModel::kPaper;
    PerceptionPipeline colour_paper(paper_params, std::make_unique<ColourBollDetector>(ColourBollParams{}));
    PerceptionParams rgb_params = params;
    rgb_params.end_effector.colour_space = EndEffectorColourSpace::kRgb;
    PerceptionPipeline colour_rgb(rgb_params, std::make_unique<ColourBollDetector>(ColourBollParams{}));
    // Ablations: depth from the window at the visible centroid; partly hidden bolls not accepted.
    PerceptionParams window_params = params;
    window_params.locator.boll_surface = false;
    PerceptionPipeline colour_window(window_params, std::make_unique<ColourBollDetector>(ColourBollParams{}));
    ColourBollParams no_partial;
    no_partial.partial_min_visible = 0.0;
    PerceptionPipeline colour_no_partial(params, std::make_unique<ColourBollDetector>(no_partial));
    ColourBollParams arc_test;
    arc_test.whole_needs_arc = true;
    PerceptionPipeline colour_arc_test(params, std::make_unique<ColourBollDetector>(arc_test));
    // Without the dome test (flat white things that are boll-sized at their depth pass as bolls).
    PerceptionParams no_dome_params = params;
    no_dome_params.boll_min_dome_fraction = 0.0;
    PerceptionPipeline colour_no_dome(no_dome_params, std::make_unique<ColourBollDetector>(ColourBollParams{}));
    std::unique_ptr<PerceptionPipeline> dnn, network;
    if (r == 0 && dnn_frames > 0) {
      dnn = std::make_unique<PerceptionPipeline>(params, std::make_unique<DarknetBollDetector>(darknet));
      network = std::make_unique<PerceptionPipeline>(params, std::make_unique<NetworkBollDetector>(network_params));
    }

    for (int i = 0; i < resolution.frames; ++i, ++done) {
      SceneParams scene = sceneFor(i, params.intrinsics);
      // The detectors know the nominal camera height only: the scene's varies around it.
      SyntheticFrame frame;
      const std::uint32_t frame_seed = seed * 100000u + static_cast<std::uint32_t>(r * 20000 + i);
      render_time.ms.push_back(timeMs([&] { frame = makeSyntheticFrame(scene, frame_seed); }));
      FrameResult result;
      const double cpu_start = threadCpuMs();
      const double ms = timeMs([&] { result = colour.process(frame.bgr, frame.cloud); });
      if (r == 0) {
        colour_time.ms.push_back(ms);
        colour_cpu.ms.push_back(threadCpuMs() - cpu_start);
      }
      const FrameScore score = scoreFrame(result, frame.layout, ScoringParams{});
      if (list_misses) {
        const auto nearest = [&](const cv::Point2d& p) {
          double best = std::numeric_limits<double>::infinity();
          for (const LocatedBoll& b : result.bolls)
            best = std::min(best, std::hypot(b.detection.centroid.x - p.x, b.detection.centroid.y - p.y));
          return best;
        };
        for (size_t b : score.missed_bolls) {
          const TrueBoll& boll = frame.layout.bolls[b];
          std::printf(
              "[miss] frame_seed %u %dx%d %s boll %zu at (%.1f, %.1f) radius %.1f px, depth %.2f m, %s, "
              "visible %.2f, nearest located detection %.1f px\n",
              frame_seed, resolution.width, resolution.height, toString(scene.lighting).c_str(), b, boll.pixel.x,
              boll.pixel.y, boll.radius_px, boll.centre.z, kCaseNames[caseOf(frame.layout, b)], boll.visible_fraction,
              nearest(boll.pixel));
        }
        for (size_t d : score.false_detections) {
          const LocatedBoll& b = result.bolls[d];
          std::printf(
              "[false] frame_seed %u %dx%d %s detection at (%.1f, %.1f) radius %.1f px, depth %.2f m, dome "
              "%.4f +- %.4f m\n",
              frame_seed, resolution.width, resolution.height, toString(scene.lighting).c_str(), b.detection.centroid.x,
              b.detection.centroid.y, b.detection.radius_px, b.position.z, b.dome_m, b.dome_sigma_m);
        }
      }
      by_light[i % 3].add(score);
      by_resolution[r].add(score);
      all.add(score);
      for (int c = 0; c < 3; ++c) by_case[c].add(score, frame.layout, static_cast<BollCase>(c));
      all_paper.add(scoreFrame(colour_paper.process(frame.bgr, frame.cloud), frame.layout, ScoringParams{}));
      all_window.add(scoreFrame(colour_window.process(frame.bgr, frame.cloud), frame.layout, ScoringParams{}));
      all_no_partial.add(scoreFrame(colour_no_partial.process(frame.bgr, frame.cloud), frame.layout, ScoringParams{}));
      all_arc_test.add(scoreFrame(colour_arc_test.process(frame.bgr, frame.cloud), frame.layout, ScoringParams{}));
      all_no_dome.add(scoreFrame(colour_no_dome.process(frame.bgr, frame.cloud), frame.layout, ScoringParams{}));
      all_rgb.add(scoreFrame(colour_rgb.process(frame.bgr, frame.cloud), frame.layout, ScoringParams{}));
      if (dnn && i < dnn_frames) dnn_time.ms.push_back(timeMs([&] { dnn->process(frame.bgr, frame.cloud); }));
      if (network && i < dnn_frames)
        network_time.ms.push_back(timeMs([&] { network->process(frame.bgr, frame.cloud); }));
      if ((done + 1) % 10 == 0 || done + 1 == total) {
        std::printf("[perception_bench] %d/%d frames (%dx%d)\n", done + 1, total, resolution.width, resolution.height);
        std::fflush(stdout);
      }
    }
  }
  std::filesystem::remove_all(dir);

  std::printf("\nperception_bench: %d synthetic frames (sun, overcast, shade in turn), OpenCV threads %d\n\n", total,
              cv::getNumThreads());
  std::printf("%-40s %6s %9s %9s %9s\n", "pipeline (1280x720)", "frames", "mean ms", "p95 ms", "max ms");
  const auto timing_row = [&](const char* name, const Timing& t) {
    std::printf("%-40s %6zu %9.2f %9.2f %9.2f\n", name, t.ms.size(), t.mean(), t.percentile(0.95), t.percentile(1.0));
  };
  timing_row("colour (end-effector + bolls + 3D)", colour_time);
  timing_row("colour, CPU time of the thread", colour_cpu);
  timing_row("tiny-YOLOv3 416x416 (+ EE + 3D)", dnn_time);
  timing_row("boll network 448x256 (+ EE + 3D)", network_time);
  timing_row("(synthetic frame rendering, all sizes)", render_time);

  std::printf("\n%-26s %5s %5s %5s %9s %7s %10s %10s %12s %6s %5s\n", "colour detector", "TP", "FP", "FN", "precision",
              "recall", "3D err m", "p95 err m", "EE found", "share", "EE FP");
  for (int l = 0; l < 3; ++l) printScores(toString(kLightings[l]), by_light[l]);
  for (int r = 0; r < 3; ++r)
    printScores(std::to_string(resolutions[r].width) + "x" + std::to_string(resolutions[r].height), by_resolution[r]);
  printScores("all (depth: ray)", all);
  printScores("all (depth: paper)", all_paper);
  printScores("all (EE: paper's RGB)", all_rgb);
  printScores("all (depth: 5x5 window)", all_window);
  printScores("all (no partial bolls)", all_no_partial);
  printScores("all (whole: arc test)", all_arc_test);
  printScores("all (no dome test)", all_no_dome);
  std::printf("\n%-26s %6s %6s %7s %10s %10s\n", "bolls by case (all sizes)", "found", "missed", "recall", "3D err m",
              "p95 err m");
  for (int c = 0; c < 3; ++c) {
    const CaseStats& stats = by_case[c];
    std::printf("%-26s %6d %6d %7.3f %10.4f %10.4f\n", kCaseNames[c], stats.found, stats.missed,
                ratio(stats.found, stats.found + stats.missed), stats.errors.meanError3d(),
                stats.errors.percentileError3d(0.95));
  }
  std::printf(
      "\nScored against bolls at least half visible; 3D error to the visible surface point on the ray through the\n"
      "boll centre. The end-effector counts as expected when at least half of its top face is visible.\n"
      "The tiny-YOLOv3's weights are random: only its time is meaningful.\n");

  NetworkFigures net_figures;
  constexpr double kMaxError3dM = 0.03;
  checkTrained(network_params, COTTON_HARVESTER_BOLL_NET_FRAMES, &net_figures);
  if (!heldout_dir.empty()) {
    const std::string error = scoreHeldout(heldout_dir, network_params, fig8, kMaxError3dM, top_fraction, &net_figures);
    if (!error.empty()) std::printf("held-out frames: %s\n", error.c_str());
  }
  printNetworkFigures(net_figures, kMaxError3dM);
  if (gap && !heldout_dir.empty()) {
    const std::string error = runHeldoutGap(heldout_dir, network_params, kMaxError3dM, top_fraction);
    if (!error.empty()) std::printf("held-out frames: %s\n", error.c_str());
  }
  if (noise_frames > 0) runNoiseCurve(noise_frames, seed, network_params, noise_network, kMaxError3dM);
  const auto fig8_recall = [&](int i) { return net_figures.fig8_run ? net_figures.fig8[i].recall() : -1.0; };
  const auto held = [&](double value) { return net_figures.heldout_frames > 0 ? value : -1.0; };

  std::printf(
      "RESULT {\"ms_per_frame_colour_720p\": %.3f, \"cpu_ms_per_frame_colour_720p\": %.3f, \"ms_per_frame_dnn\": %.3f, "
      "\"precision\": %.4f, "
      "\"recall\": %.4f, \"boll_3d_err_m\": %.4f, \"boll_3d_err_p95_m\": %.4f, \"end_effector_found\": %.4f, "
      "\"end_effector_found_paper_rgb\": %.4f, \"frames\": %d, \"ms_per_frame_darknet_random\": %.3f, "
      "\"network_trained\": %d, \"heldout_frames\": %d, \"network_precision\": %.4f, \"network_recall\": %.4f, "
      "\"network_boll_3d_err_p95_m\": %.4f, \"heldout_colour_precision\": %.4f, \"heldout_colour_recall\": %.4f, "
      "\"fig8_linear_recall\": %.4f, \"fig8_nearest_recall\": %.4f, \"fig8_none_recall\": %.4f, "
      "\"heldout_colour_boll_3d_err_p95_m\": %.4f, \"heldout_colour_recall_centre\": %.4f, "
      "\"network_recall_centre\": %.4f, \"boll_centre_err_p95_m\": %.4f}\n",
      colour_time.mean(), colour_cpu.mean(), network_time.mean(), all.precision(), all.recall(), all.meanError3d(),
      all.percentileError3d(0.95), ratio(all.end_effector_found, all.end_effector_expected),
      ratio(all_rgb.end_effector_found, all_rgb.end_effector_expected), total, dnn_time.mean(), net_figures.trained,
      net_figures.heldout_frames, held(net_figures.network.precision()), held(net_figures.network.recall()),
      held(net_figures.network.percentileError3d(0.95)), held(net_figures.colour.precision()),
      held(net_figures.colour.recall()), fig8_recall(0), fig8_recall(1), fig8_recall(2),
      held(net_figures.colour.percentileError3d(0.95)), held(net_figures.colour_centre.recall()),
      held(net_figures.network_centre.recall()), thorvald_common::percentile(all.centre_errors_3d_m, 0.95));
  return 0;
}
