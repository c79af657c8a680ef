#pragma once

#include <vector>

#include "cotton_harvester/perception/perception_pipeline.h"
#include "cotton_harvester/testing/synthetic_scene.h"

namespace cotton_harvester {
namespace perception {

/// How detections are matched to the truth.
struct ScoringParams {
  /// Bolls with less of their silhouette visible are not counted as missed when undetected [0, 1].
  double min_visible_fraction = 0.5;
  /// A detection matches a boll when its centroid is within max(min_match_px, boll radius [px]) of the boll's
  /// projected centre [px].
  double min_match_px = 6.0;
};

/// The score of one frame.
struct FrameScore {
  int true_positives = 0;           ///< detections matched to a boll that had to be found
  int false_positives = 0;          ///< detections matched to no boll
  int false_negatives = 0;          ///< visible bolls no detection matched
  int matched_hidden = 0;           ///< detections matched to a mostly hidden boll (neither true nor false positive)
  std::vector<double> errors_3d_m;  ///< |position - true surface point| of each matched detection [m]
  /// |centre - true centre| of each matched detection (LocatedBoll::centre against TrueBoll::centre) [m]
  std::vector<double> centre_errors_3d_m;
  std::vector<size_t> matched_bolls;       ///< the true boll (index into SceneLayout::bolls) of each errors_3d_m entry
  std::vector<size_t> matched_detections;  ///< the detection (index into FrameResult::bolls) of each entry
  std::vector<size_t> missed_bolls;        ///< the true bolls counted as false negatives
  std::vector<size_t> false_detections;    ///< the detections (index into FrameResult::bolls) matched to no boll
  bool end_effector_expected = false;      ///< in view and at least min_visible_fraction of its top face visible
  bool end_effector_found = false;         ///< found in the image
  bool end_effector_located = false;       ///< found and located in 3D
  bool end_effector_false = false;         ///< found although there is none in the scene
  double end_effector_error_m = 0.0;       ///< |located - true top centre| when both exist [m]
};

/// Matches a frame's located bolls one to one with the true bolls, nearest pairs first.
FrameScore scoreFrame(const FrameResult& result, const SceneLayout& truth, const ScoringParams& params);

/// Totals over many frames.
struct ScoreSummary {
  int true_positives = 0, false_positives = 0, false_negatives = 0;
  std::vector<double> errors_3d_m;
  std::vector<double> centre_errors_3d_m;  ///< FrameScore::centre_errors_3d_m of every frame [m]
  int end_effector_expected = 0, end_effector_found = 0, end_effector_false = 0;
  std::vector<double> end_effector_errors_m;

  void add(const FrameScore& score);
  double precision() const;                  ///< TP / (TP + FP), 1 when nothing was detected
  double recall() const;                     ///< TP / (TP + FN), 1 when nothing had to be found
  double meanError3d() const;                ///< [m], 0 when no match
  double percentileError3d(double q) const;  ///< q in [0, 1] [m]
};

}  // namespace perception
}  // namespace cotton_harvester
