// perception_bench: time per 720p frame of the colour pipeline and of the tiny-YOLOv3 path, and detection
// precision/recall and 3D error of the colour pipeline on synthetic frames with ground truth.
//   rosrun cotton_harvester perception_bench [--frames N] [--dnn-frames N] [--seed S]

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <numeric>
#include <string>
#include <vector>

#include <unistd.h>

#include <opencv2/core/utility.hpp>

#include "cotton_harvester/perception/colour_boll_detector.h"
#include "cotton_harvester/perception/darknet_boll_detector.h"
#include "cotton_harvester/perception/darknet_net_writer.h"
#include "cotton_harvester/perception/detection_scoring.h"
#include "cotton_harvester/perception/perception_pipeline.h"
#include "cotton_harvester/perception/scene_renderer.h"

using namespace cotton_harvester::perception;
using Clock = std::chrono::steady_clock;

namespace {

struct Timing {
  std::vector<double> ms;
  double mean() const { return ms.empty() ? 0.0 : std::accumulate(ms.begin(), ms.end(), 0.0) / ms.size(); }
  double percentile(double q) const {
    if (ms.empty()) return 0.0;
    std::vector<double> sorted = ms;
    std::sort(sorted.begin(), sorted.end());
    return sorted[std::min(sorted.size() - 1, static_cast<size_t>(q * (sorted.size() - 1) + 0.5))];
  }
};

template <typename F>
double timeMs(F&& f) {
  const auto start = Clock::now();
  f();
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

void printScores(const char* name, const ScoreSummary& s) {
  std::printf("%-22s %5d %5d %5d %9.3f %7.3f %10.4f %10.4f %7d/%-4d %9.4f\n", name, s.true_positives, s.false_positives,
              s.false_negatives, s.precision(), s.recall(), s.meanError3d(), s.percentileError3d(0.95),
              s.end_effector_found, s.end_effector_expected,
              s.end_effector_errors_m.empty()
                  ? 0.0
                  : std::accumulate(s.end_effector_errors_m.begin(), s.end_effector_errors_m.end(), 0.0) /
                        s.end_effector_errors_m.size());
}

}  // namespace

int main(int argc, char** argv) {
  int frames = 200, dnn_frames = 200;
  std::uint32_t seed = 1;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--frames"))
      frames = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--dnn-frames"))
      dnn_frames = std::atoi(argv[i + 1]);
    else if (!std::strcmp(argv[i], "--seed"))
      seed = static_cast<std::uint32_t>(std::atoi(argv[i + 1]));
    else {
      std::fprintf(stderr, "usage: perception_bench [--frames N] [--dnn-frames N] [--seed S]\n");
      return 2;
    }
  }
  if (frames < 1 || dnn_frames < 0) {
    std::fprintf(stderr, "perception_bench: --frames must be >= 1 and --dnn-frames >= 0\n");
    return 2;
  }

  // The tiny-YOLOv3-sized network (random weights: its detections mean nothing, its cost is the real one).
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("cotton_harvester_bench_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  DarknetParams darknet;
  darknet.cfg_path = (dir / "tiny_yolov3_boll.cfg").string();
  darknet.weights_path = (dir / "tiny_yolov3_boll.weights").string();
  writeDarknetFiles(tinyYoloV3Layout(416, 416, 1, seed), darknet.cfg_path, darknet.weights_path);

  PerceptionParams params;
  PerceptionPipeline colour(params, std::make_unique<ColourBollDetector>(ColourBollParams{}));
  PerceptionParams paper_params = params;
  paper_params.locator.depth_model = DepthModel::kPaper;
  PerceptionPipeline colour_paper(paper_params, std::make_unique<ColourBollDetector>(ColourBollParams{}));
  PerceptionPipeline dnn(params, std::make_unique<DarknetBollDetector>(darknet));

  ScoreSummary by_light[2], all, all_paper;
  Timing colour_time, dnn_time, render_time;
  for (int i = 0; i < frames; ++i) {
    SceneParams scene;
    scene.lighting = i % 2 == 0 ? Lighting::kSunny : Lighting::kCloudy;
    SyntheticFrame frame;
    render_time.ms.push_back(timeMs([&] { frame = makeSyntheticFrame(scene, seed * 100000u + i); }));
    FrameResult result;
    colour_time.ms.push_back(timeMs([&] { result = colour.process(frame.bgr, frame.cloud); }));
    const FrameScore score = scoreFrame(result, frame.layout, ScoringParams{});
    by_light[i % 2].add(score);
    all.add(score);
    all_paper.add(scoreFrame(colour_paper.process(frame.bgr, frame.cloud), frame.layout, ScoringParams{}));
    if (i < dnn_frames) dnn_time.ms.push_back(timeMs([&] { dnn.process(frame.bgr, frame.cloud); }));
  }
  std::filesystem::remove_all(dir);

  const double budget_ms = 1000.0 / 60.0;
  std::printf("perception_bench: %d synthetic 1280x720 frames (half sunny, half cloudy), OpenCV threads %d\n\n", frames,
              cv::getNumThreads());
  std::printf("%-34s %6s %9s %9s %9s %12s\n", "pipeline", "frames", "mean ms", "p95 ms", "max ms", "60 fps budget");
  const auto timing_row = [&](const char* name, const Timing& t) {
    std::printf("%-34s %6zu %9.2f %9.2f %9.2f %11.0f%%\n", name, t.ms.size(), t.mean(), t.percentile(0.95),
                t.percentile(1.0), 100.0 * t.mean() / budget_ms);
  };
  timing_row("colour (end-effector + bolls + 3D)", colour_time);
  timing_row("tiny-YOLOv3 416x416 (+ EE + 3D)", dnn_time);
  timing_row("(synthetic frame rendering)", render_time);

  std::printf("\n%-22s %5s %5s %5s %9s %7s %10s %10s %12s %9s\n", "colour detector", "TP", "FP", "FN", "precision",
              "recall", "3D err m", "p95 err m", "EE found", "EE err m");
  printScores("sunny", by_light[0]);
  printScores("cloudy", by_light[1]);
  printScores("all (depth: ray)", all);
  printScores("all (depth: paper)", all_paper);
  std::printf(
      "\nScored against bolls at least half visible; 3D error to the visible surface point on the ray\n"
      "through the boll centre. The DNN's weights are random: only its time is meaningful.\n");

  std::printf(
      "RESULT {\"ms_per_frame_colour\": %.3f, \"ms_per_frame_dnn\": %.3f, \"precision\": %.4f, "
      "\"recall\": %.4f, \"boll_3d_err_m\": %.4f}\n",
      colour_time.mean(), dnn_time.mean(), all.precision(), all.recall(), all.meanError3d());
  return 0;
}
