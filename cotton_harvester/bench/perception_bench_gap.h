#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "cotton_harvester/perception/network_boll_detector.h"
#include "cotton_harvester/perception/perception_pipeline.h"
#include "cotton_harvester/testing/detection_scoring.h"
#include "cotton_harvester/testing/synthetic_scene.h"

namespace cotton_harvester {
namespace perception {

/// Where the bolls that must be found (at least half visible) are lost between the image and 3D, for one detector
/// (perception_bench --gap): no 2D detection; detected but dropped for lack of depth or as implausible in 3D (ground,
/// size, dome); located but further than the limit from the true surface point; found. The 3D error of the located
/// ones is split along the ray through the true centre (signed: + deeper than the truth) and across it, against the
/// true surface point and, for LocatedBoll::centre, against the true centre.
struct GapTable {
  int visible = 0, no_2d = 0, no_depth = 0, implausible = 0, located = 0, within = 0, centre_within = 0;
  int size_fallback = 0, size_fallback_within = 0;      ///< located by image size, and of those within the limit
  std::vector<double> along_m, across_m;                ///< position - true surface point
  std::vector<double> centre_along_m, centre_across_m;  ///< centre - true centre
  /// The share of the true disc (within 0.8 of its image radius) whose cloud pixels carry depth, in 4 bins (< 0.1,
  /// < 0.3, < 0.6, >= 0.6): bolls detected in 2D, located, found within the limit.
  int share_detected[4] = {0, 0, 0, 0}, share_located[4] = {0, 0, 0, 0}, share_within[4] = {0, 0, 0, 0};

  /// Adds one frame: `result` of the pipeline, the truth and its cloud.
  void add(const FrameResult& result, const SceneLayout& truth, const cv::Mat& cloud, double max_error_m);
};

/// The along/across split of `error` (estimate - truth) with respect to the unit ray through `truth_point`: the
/// signed along-ray part (+ farther from the camera) and the size of the rest [m].
void splitAlongRay(const cv::Point3d& error, const cv::Point3d& truth_point, double* along_m, double* across_m);

/// Share of the pixels of a disc (centre, 0.8 radius_px) whose cloud point is finite [0, 1]; 0 outside the cloud.
double validDepthShare(const cv::Mat& cloud, const cv::Point2d& centre, double radius_px);

/// Prints the tables (one row per named GapTable).
void printGapTables(const std::vector<std::string>& names, const std::vector<const GapTable*>& tables,
                    double max_error_m);

/// A passive-stereo depth model for the noise curve: sigma_z = z^2 sigma_disparity / (f b) (ZED: b = 0.12 m),
/// the noise correlated over the matcher's block (7 px), and holes where the matcher finds nothing: saturated pixels
/// (a channel >= 250) and textureless ones (grey standard deviation over the block below texture_min).
struct StereoNoise {
  double sigma_disparity_px = 0.0;
  double baseline_m = 0.12;
  bool holes = true;
  double texture_min = 4.0;  ///< [grey levels]
  int block_px = 7;
};

/// Replaces `cloud`'s depth (CV_32FC3, exact) with the model's: each point moved along its pixel's ray.
void applyStereoNoise(const cv::Mat& bgr, const StereoNoise& noise, double focal_px, std::uint32_t seed,
                      cv::Mat* cloud);

/// perception_bench --gap: the GapTables of the colour and network pipelines (default parameters but the detector),
/// and of both with the size fallback on, over every held-out frame of `dir` (top_fraction as scoreHeldout's). Returns
/// an empty string or what went wrong.
std::string runHeldoutGap(const std::string& dir, const NetworkParams& network, double max_error_m,
                          double top_fraction);

/// perception_bench --noise-curve N: recall, precision and 3D error p95 of the default (colour) pipeline, and of the
/// network when with_network, against passive-stereo depth noise (StereoNoise), N synthetic 720p frames per level
/// (seeds from `seed`); a boll counts as found when located within max_error_m of its surface point.
void runNoiseCurve(int frames, std::uint32_t seed, const NetworkParams& network, bool with_network, double max_error_m);

}  // namespace perception
}  // namespace cotton_harvester
