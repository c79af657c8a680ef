#include "network_figures.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>

#include <opencv2/imgcodecs.hpp>

#include "cotton_harvester/perception/colour_boll_detector.h"
#include "cotton_harvester/perception/perception_pipeline.h"
#include "cotton_harvester/testing/heldout_frames.h"

namespace cotton_harvester {
namespace perception {

namespace fs = std::filesystem;

namespace {

double iou(const cv::Rect2d& a, const cv::Rect2d& b) {
  const double common = (a & b).area();
  return common / (a.area() + b.area() - common);
}

void row(const char* name, const ScoreSummary& s) {
  std::printf("%-34s %5d %5d %5d %9.3f %7.3f %10.4f %10.4f %5d/%-5d\n", name, s.true_positives, s.false_positives,
              s.false_negatives, s.precision(), s.recall(), s.meanError3d(), s.percentileError3d(0.95),
              s.end_effector_found, s.end_effector_expected);
}

}  // namespace

void checkTrained(const NetworkParams& params, const std::string& frames_dir, NetworkFigures* f) {
  NetworkBollDetector detector(params);
  for (const auto& entry : fs::directory_iterator(frames_dir)) {
    if (entry.path().extension() != ".png") continue;
    const cv::Mat bgr = cv::imread(entry.path().string(), cv::IMREAD_COLOR);
    std::ifstream in(fs::path(entry.path()).replace_extension(".txt"));
    std::vector<cv::Rect2d> truth;
    int c = 0;
    double x = 0, y = 0, w = 0, h = 0;
    while (in >> c >> x >> y >> w >> h)
      if (c == 0) truth.emplace_back((x - 0.5 * w) * bgr.cols, (y - 0.5 * h) * bgr.rows, w * bgr.cols, h * bgr.rows);
    const std::vector<BollDetection> found = detector.detect(bgr, cv::Mat());
    f->trained_labels += static_cast<int>(truth.size());
    for (const cv::Rect2d& t : truth) {
      bool hit = false;
      for (const BollDetection& d : found) hit = hit || iou(t, d.box) >= 0.4;
      f->trained_found += hit ? 1 : 0;
    }
    for (const BollDetection& d : found) {
      bool hit = false;
      for (const cv::Rect2d& t : truth) hit = hit || iou(t, d.box) >= 0.4;
      f->trained_false += hit ? 0 : 1;
    }
  }
  const int detections = f->trained_found + f->trained_false;
  f->trained = f->trained_labels > 0 && 2 * f->trained_found >= f->trained_labels &&
                       (detections == 0 || 2 * f->trained_found >= detections)
                   ? 1
                   : 0;
}

std::string scoreHeldout(const std::string& dir, const NetworkParams& params, bool fig8, double max_error_m,
                         double top_fraction, NetworkFigures* f) {
  const std::vector<std::string> names = listHeldoutFrames(dir);
  if (names.empty()) return "no held-out frames (images/, depth/, truth/) in '" + dir + "'";
  PerceptionParams pp;
  pp.boll_top_fraction = top_fraction;
  PerceptionPipeline colour(pp, std::make_unique<ColourBollDetector>(ColourBollParams{}));
  PerceptionPipeline network(pp, std::make_unique<NetworkBollDetector>(params));
  std::vector<std::unique_ptr<PerceptionPipeline>> resized;
  const InputResize resizes[3] = {InputResize::kLinear, InputResize::kNearest, InputResize::kNone};
  for (int i = 0; fig8 && i < 3; ++i) {
    NetworkParams p = params;
    p.resize = resizes[i];
    resized.push_back(std::make_unique<PerceptionPipeline>(pp, std::make_unique<NetworkBollDetector>(p)));
  }
  f->fig8_run = fig8;
  for (const std::string& name : names) {
    HeldoutFrame frame;
    std::string error;
    if (!loadHeldoutFrame(dir, name, pp.intrinsics, &frame, &error, top_fraction)) return error;
    const auto score = [&](PerceptionPipeline& pipeline) {
      return withinDistance(scoreFrame(pipeline.process(frame.bgr, frame.cloud), frame.truth, ScoringParams{}),
                            max_error_m);
    };
    const FrameResult n_result = network.process(frame.bgr, frame.cloud),
                      c_result = colour.process(frame.bgr, frame.cloud);
    const FrameScore n_raw = scoreFrame(n_result, frame.truth, ScoringParams{}),
                     c_raw = scoreFrame(c_result, frame.truth, ScoringParams{});
    const FrameScore n = withinDistance(n_raw, max_error_m), c = withinDistance(c_raw, max_error_m);
    f->network_centre.add(withinDistance(n_raw, max_error_m, true));
    f->colour_centre.add(withinDistance(c_raw, max_error_m, true));
    f->network.add(n);
    f->colour.add(c);
    f->network_day[frame.sunny ? 1 : 0].add(n);
    f->colour_day[frame.sunny ? 1 : 0].add(c);
    for (size_t i = 0; i < resized.size(); ++i) f->fig8[i].add(score(*resized[i]));
    ++f->heldout_frames;
  }
  return "";
}

void printNetworkFigures(const NetworkFigures& f, double max_error_m) {
  std::printf("\nboll network: %d of %d labelled bolls found on the shipped frames, %d false -> network_trained %d\n",
              f.trained_found, f.trained_labels, f.trained_false, f.trained);
  if (f.heldout_frames == 0) return;
  std::printf("\nheld-out datasheet frames: %d (a boll found when located within %.0f mm of its visible top)\n",
              f.heldout_frames, 1e3 * max_error_m);
  std::printf("%-34s %5s %5s %5s %9s %7s %10s %10s %11s\n", "detector", "TP", "FP", "FN", "precision", "recall",
              "3D err m", "p95 err m", "EE found");
  row("network", f.network);
  row("network, overcast", f.network_day[0]);
  row("network, sunny", f.network_day[1]);
  row("colour", f.colour);
  row("colour, overcast", f.colour_day[0]);
  row("colour, sunny", f.colour_day[1]);
  std::printf("scored by the centre estimate (LocatedBoll::centre within %.0f mm of the boll's centre)\n",
              1e3 * max_error_m);
  row("network, centre", f.network_centre);
  row("colour, centre", f.colour_centre);
  if (!f.fig8_run) return;
  std::printf("\nFigure 8 (paper): the network's input from the 1280x720 frame\n");
  row("bilinear resize", f.fig8[0]);
  row("nearest-neighbour resize", f.fig8[1]);
  row("no interpolation (top-left crop)", f.fig8[2]);
}

}  // namespace perception
}  // namespace cotton_harvester
