#include "perception_bench_gap.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>

#include <opencv2/imgproc.hpp>
#include <thorvald_common/bench_statistics.h>

#include "cotton_harvester/perception/colour_boll_detector.h"
#include "cotton_harvester/testing/heldout_frames.h"
#include "cotton_harvester/testing/scene_renderer.h"

namespace cotton_harvester {
namespace perception {

namespace {

int shareBin(double share) { return share < 0.1 ? 0 : share < 0.3 ? 1 : share < 0.6 ? 2 : 3; }

double norm(const cv::Point3d& p) { return std::sqrt(p.dot(p)); }

}  // namespace

void splitAlongRay(const cv::Point3d& error, const cv::Point3d& truth_point, double* along_m, double* across_m) {
  const double n = norm(truth_point);
  const cv::Point3d ray = n > 0.0 ? truth_point * (1.0 / n) : cv::Point3d(0.0, 0.0, 1.0);
  *along_m = error.dot(ray);
  *across_m = norm(error - ray * *along_m);
}

double validDepthShare(const cv::Mat& cloud, const cv::Point2d& centre, double radius_px) {
  const double r = 0.8 * radius_px;
  int all = 0, valid = 0;
  for (int v = static_cast<int>(std::floor(centre.y - r)); v <= static_cast<int>(std::ceil(centre.y + r)); ++v)
    for (int u = static_cast<int>(std::floor(centre.x - r)); u <= static_cast<int>(std::ceil(centre.x + r)); ++u) {
      if ((u - centre.x) * (u - centre.x) + (v - centre.y) * (v - centre.y) > r * r) continue;
      ++all;
      if (u < 0 || v < 0 || u >= cloud.cols || v >= cloud.rows) continue;
      valid += std::isfinite(cloud.at<cv::Vec3f>(v, u)[2]) ? 1 : 0;
    }
  return all > 0 ? static_cast<double>(valid) / all : 0.0;
}

void GapTable::add(const FrameResult& result, const SceneLayout& truth, const cv::Mat& cloud, double max_error_m) {
  // Every detection, located or dropped, matched to the truth in the image as scoreFrame does.
  FrameResult all = result;
  const size_t located_count = result.bolls.size();
  for (const FrameResult::Dropped& dropped : result.dropped) {
    LocatedBoll boll;
    boll.detection = dropped.detection;
    all.bolls.push_back(boll);
  }
  const ScoringParams scoring;
  for (const TrueBoll& boll : truth.bolls) visible += boll.visible_fraction >= scoring.min_visible_fraction ? 1 : 0;
  const FrameScore score = scoreFrame(all, truth, scoring);
  no_2d += static_cast<int>(score.missed_bolls.size());
  std::vector<int> detection_of(truth.bolls.size(), -1);
  for (size_t i = 0; i < score.matched_bolls.size(); ++i)
    detection_of[score.matched_bolls[i]] = static_cast<int>(score.matched_detections[i]);
  for (size_t b = 0; b < truth.bolls.size(); ++b) {
    const int d = detection_of[b];
    if (d < 0) continue;
    const TrueBoll& boll = truth.bolls[b];
    const int bin = shareBin(validDepthShare(cloud, boll.pixel, boll.radius_px));
    ++share_detected[bin];
    if (static_cast<size_t>(d) >= located_count) {
      const bool lacked_depth = result.dropped[d - located_count].no_depth;
      no_depth += lacked_depth ? 1 : 0;
      implausible += lacked_depth ? 0 : 1;
      continue;
    }
    const LocatedBoll& found = result.bolls[d];
    ++located;
    ++share_located[bin];
    double along = 0.0, across = 0.0;
    splitAlongRay(found.position - boll.surface, boll.centre, &along, &across);
    along_m.push_back(along);
    across_m.push_back(across);
    const bool ok = norm(found.position - boll.surface) <= max_error_m;
    within += ok ? 1 : 0;
    share_within[bin] += ok ? 1 : 0;
    splitAlongRay(found.centre - boll.centre, boll.centre, &along, &across);
    centre_along_m.push_back(along);
    centre_across_m.push_back(across);
    centre_within += norm(found.centre - boll.centre) <= max_error_m ? 1 : 0;
    if (found.depth_source == BollDepthSource::kImageSize) {
      ++size_fallback;
      size_fallback_within += ok ? 1 : 0;
    }
  }
}

void printGapTables(const std::vector<std::string>& names, const std::vector<const GapTable*>& tables,
                    double max_error_m) {
  using thorvald_common::percentile;
  const auto abs_of = [](const std::vector<double>& v) {
    std::vector<double> a(v.size());
    std::transform(v.begin(), v.end(), a.begin(), [](double x) { return std::abs(x); });
    return a;
  };
  std::printf("\nwhere the bolls (>= 0.5 visible) are lost between 2D and 3D (found: within %.0f mm)\n",
              1e3 * max_error_m);
  std::printf("%-22s %7s %6s %8s %8s %8s %6s %6s %8s %9s\n", "detector", "visible", "no 2D", "no depth", "implaus.",
              "located", "found", "> lim", "by size", "size ok");
  for (size_t i = 0; i < tables.size(); ++i) {
    const GapTable& t = *tables[i];
    std::printf("%-22s %7d %6d %8d %8d %8d %6d %6d %8d %9d\n", names[i].c_str(), t.visible, t.no_2d, t.no_depth,
                t.implausible, t.located, t.within, t.located - t.within, t.size_fallback, t.size_fallback_within);
  }
  std::printf(
      "\n3D error of the located bolls [mm]: along the ray (+ deeper; median, p5, p95) and across it (median, "
      "p95)\n");
  std::printf("%-22s %-22s %8s %8s %8s %8s %8s %8s\n", "detector", "point vs truth", "along", "p5", "p95", "|along|95",
              "across", "p95");
  for (size_t i = 0; i < tables.size(); ++i) {
    const GapTable& t = *tables[i];
    const auto row = [&](const char* what, const std::vector<double>& along, const std::vector<double>& across,
                         int within) {
      std::printf("%-22s %-22s %8.1f %8.1f %8.1f %8.1f %8.1f %8.1f   within: %d\n", names[i].c_str(), what,
                  1e3 * percentile(along, 0.5), 1e3 * percentile(along, 0.05), 1e3 * percentile(along, 0.95),
                  1e3 * percentile(abs_of(along), 0.95), 1e3 * percentile(across, 0.5), 1e3 * percentile(across, 0.95),
                  within);
    };
    row("surface vs surface", t.along_m, t.across_m, t.within);
    row("centre vs centre", t.centre_along_m, t.centre_across_m, t.centre_within);
  }
  std::printf("\nby the share of the boll's disc with depth in the cloud: detected / located / found\n");
  std::printf("%-22s %16s %16s %16s %16s\n", "detector", "< 0.1", "0.1-0.3", "0.3-0.6", ">= 0.6");
  for (size_t i = 0; i < tables.size(); ++i) {
    const GapTable& t = *tables[i];
    std::printf("%-22s", names[i].c_str());
    for (int b = 0; b < 4; ++b)
      std::printf("   %4d/%4d/%4d", t.share_detected[b], t.share_located[b], t.share_within[b]);
    std::printf("\n");
  }
}

void applyStereoNoise(const cv::Mat& bgr, const StereoNoise& noise, double focal_px, std::uint32_t seed,
                      cv::Mat* cloud) {
  cv::RNG rng(seed);
  cv::Mat n(cloud->size(), CV_32F);
  rng.fill(n, cv::RNG::NORMAL, 0.0, 1.0);
  // The matcher's block correlates the error over its size; scaled back to unit sigma.
  const cv::Size block(noise.block_px, noise.block_px);
  cv::blur(n, n, block);
  n *= static_cast<float>(noise.block_px);
  cv::Mat holes = cv::Mat::zeros(cloud->size(), CV_8U);
  if (noise.holes) {
    cv::Mat grey, grey_f, mean, mean_sq, channel_max;
    cv::cvtColor(bgr, grey, cv::COLOR_BGR2GRAY);
    grey.convertTo(grey_f, CV_32F);
    cv::blur(grey_f, mean, block);
    cv::blur(grey_f.mul(grey_f), mean_sq, block);
    cv::Mat variance = mean_sq - mean.mul(mean);
    holes = variance < noise.texture_min * noise.texture_min;
    std::vector<cv::Mat> channels;
    cv::split(bgr, channels);
    channel_max = cv::max(cv::max(channels[0], channels[1]), channels[2]);
    holes |= channel_max >= 250;
  }
  const double k = noise.sigma_disparity_px / (focal_px * noise.baseline_m);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int v = 0; v < cloud->rows; ++v) {
    cv::Vec3f* p = cloud->ptr<cv::Vec3f>(v);
    const float* e = n.ptr<float>(v);
    const uint8_t* hole = holes.ptr<uint8_t>(v);
    for (int u = 0; u < cloud->cols; ++u) {
      const float z = p[u][2];
      if (!std::isfinite(z) || !(z > 0.0f)) continue;
      if (hole[u]) {
        p[u] = cv::Vec3f(nan, nan, nan);
        continue;
      }
      p[u] *= static_cast<float>((z + k * z * z * e[u]) / z);
    }
  }
}

std::string runHeldoutGap(const std::string& dir, const NetworkParams& network, double max_error_m,
                          double top_fraction) {
  const std::vector<std::string> names = listHeldoutFrames(dir);
  if (names.empty()) return "no held-out frames (images/, depth/, truth/) in '" + dir + "'";
  PerceptionParams params;
  params.boll_top_fraction = top_fraction;
  PerceptionParams sized = params;
  sized.size_fallback = true;
  std::vector<std::unique_ptr<PerceptionPipeline>> pipelines;
  pipelines.push_back(
      std::make_unique<PerceptionPipeline>(params, std::make_unique<ColourBollDetector>(ColourBollParams{})));
  pipelines.push_back(std::make_unique<PerceptionPipeline>(params, std::make_unique<NetworkBollDetector>(network)));
  pipelines.push_back(
      std::make_unique<PerceptionPipeline>(sized, std::make_unique<ColourBollDetector>(ColourBollParams{})));
  pipelines.push_back(std::make_unique<PerceptionPipeline>(sized, std::make_unique<NetworkBollDetector>(network)));
  std::vector<GapTable> tables(pipelines.size());
  for (const std::string& name : names) {
    HeldoutFrame frame;
    std::string error;
    if (!loadHeldoutFrame(dir, name, params.intrinsics, &frame, &error, top_fraction)) return error;
    for (size_t i = 0; i < pipelines.size(); ++i)
      tables[i].add(pipelines[i]->process(frame.bgr, frame.cloud), frame.truth, frame.cloud, max_error_m);
  }
  std::printf("\nheld-out frames: %zu", names.size());
  printGapTables({"colour", "network", "colour, size fallback", "network, size fallback"},
                 {&tables[0], &tables[1], &tables[2], &tables[3]}, max_error_m);
  return "";
}

void runNoiseCurve(int frames, std::uint32_t seed, const NetworkParams& network, bool with_network,
                   double max_error_m) {
  struct Level {
    const char* name;
    StereoNoise noise;
  };
  const auto level = [](double sigma, bool holes) {
    StereoNoise n;
    n.sigma_disparity_px = sigma;
    n.holes = holes;
    return n;
  };
  const Level levels[] = {{"exact depth", level(0.0, false)},  {"0.1 px, no holes", level(0.1, false)},
                          {"0.1 px, holes", level(0.1, true)}, {"0.25 px, holes", level(0.25, true)},
                          {"0.5 px, holes", level(0.5, true)}, {"1.0 px, holes", level(1.0, true)}};
  PerceptionParams params;
  PerceptionPipeline colour(params, std::make_unique<ColourBollDetector>(ColourBollParams{}));
  std::unique_ptr<PerceptionPipeline> net;
  if (with_network) net = std::make_unique<PerceptionPipeline>(params, std::make_unique<NetworkBollDetector>(network));
  const double focal = params.intrinsics.fx;
  std::printf(
      "\ndepth-noise curve: %d synthetic 1280x720 frames a level (seed %u); passive stereo sigma_z = z^2 "
      "sigma_d / (f b), b 0.12 m,\ncorrelated over 7 px; holes where saturated or textureless; found: within "
      "%.0f mm of the surface point\n",
      frames, seed, 1e3 * max_error_m);
  std::printf("%-18s %9s %-8s %9s %7s %10s %10s %9s %10s\n", "sigma_d", "sz@2m mm", "detector", "precision", "recall",
              "3D err m", "p95 err m", "no depth", "depth share");
  for (const Level& l : levels) {
    ScoreSummary summary[2];
    int no_depth[2] = {0, 0};
    double share = 0.0;
    int bolls = 0;
    for (int i = 0; i < frames; ++i) {
      SceneParams scene;
      scene.intrinsics = params.intrinsics;
      scene.depth_noise_per_m2 = 0.0;
      scene.hole_fraction = 0.0;
      scene.hole_blobs = 0;
      SyntheticFrame frame = makeSyntheticFrame(scene, seed * 1000u + static_cast<std::uint32_t>(i));
      applyStereoNoise(frame.bgr, l.noise, focal, seed * 7919u + static_cast<std::uint32_t>(i), &frame.cloud);
      for (const TrueBoll& b : frame.layout.bolls) {
        if (b.visible_fraction < 0.5) continue;
        share += validDepthShare(frame.cloud, b.pixel, b.radius_px);
        ++bolls;
      }
      for (int d = 0; d < (net ? 2 : 1); ++d) {
        const FrameResult result = (d == 0 ? colour : *net).process(frame.bgr, frame.cloud);
        no_depth[d] += result.bolls_without_depth;
        summary[d].add(withinDistance(scoreFrame(result, frame.layout, ScoringParams{}), max_error_m));
      }
    }
    for (int d = 0; d < (net ? 2 : 1); ++d)
      std::printf("%-18s %9.1f %-8s %9.3f %7.3f %10.4f %10.4f %9d %10.2f\n", l.name,
                  1e3 * 4.0 * l.noise.sigma_disparity_px / (focal * l.noise.baseline_m), d == 0 ? "colour" : "network",
                  summary[d].precision(), summary[d].recall(), summary[d].meanError3d(),
                  summary[d].percentileError3d(0.95), no_depth[d], bolls > 0 ? share / bolls : 0.0);
  }
}

}  // namespace perception
}  // namespace cotton_harvester
