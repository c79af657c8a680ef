#include "cotton_harvester/testing/detection_scoring.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <tuple>

namespace cotton_harvester {
namespace perception {

FrameScore scoreFrame(const FrameResult& result, const SceneLayout& truth, const ScoringParams& params) {
  FrameScore score;
  std::vector<std::tuple<double, size_t, size_t>> pairs;  // distance [px], detection, boll
  for (size_t d = 0; d < result.bolls.size(); ++d) {
    for (size_t b = 0; b < truth.bolls.size(); ++b) {
      const TrueBoll& boll = truth.bolls[b];
      if (boll.visible_fraction <= 0.0) continue;
      const cv::Point2d offset = result.bolls[d].detection.centroid - boll.pixel;
      const double distance = std::hypot(offset.x, offset.y);
      if (distance <= std::max(params.min_match_px, boll.radius_px)) pairs.emplace_back(distance, d, b);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  std::vector<bool> detection_used(result.bolls.size(), false), boll_used(truth.bolls.size(), false);
  for (const auto& [distance, d, b] : pairs) {
    if (detection_used[d] || boll_used[b]) continue;
    detection_used[d] = boll_used[b] = true;
    if (truth.bolls[b].visible_fraction >= params.min_visible_fraction) {
      ++score.true_positives;
      const cv::Point3d error = result.bolls[d].position - truth.bolls[b].surface;
      score.errors_3d_m.push_back(std::sqrt(error.dot(error)));
      const cv::Point3d centre_error = result.bolls[d].centre - truth.bolls[b].centre;
      score.centre_errors_3d_m.push_back(std::sqrt(centre_error.dot(centre_error)));
      score.matched_bolls.push_back(b);
      score.matched_detections.push_back(d);
    } else {
      ++score.matched_hidden;
    }
  }
  score.false_positives = static_cast<int>(std::count(detection_used.begin(), detection_used.end(), false));
  for (size_t d = 0; d < detection_used.size(); ++d)
    if (!detection_used[d]) score.false_detections.push_back(d);
  for (size_t b = 0; b < truth.bolls.size(); ++b) {
    if (!boll_used[b] && truth.bolls[b].visible_fraction >= params.min_visible_fraction) {
      ++score.false_negatives;
      score.missed_bolls.push_back(b);
    }
  }

  // The end-effector has to be found when at least half of its top face is in the image and not under leaves.
  score.end_effector_expected =
      truth.end_effector && truth.end_effector->visible_fraction >= params.min_visible_fraction;
  score.end_effector_found = result.end_effector_image.has_value();
  score.end_effector_located = result.end_effector.has_value();
  score.end_effector_false = !truth.end_effector && result.end_effector_image.has_value();
  if (truth.end_effector && result.end_effector) {
    const cv::Point3d error = result.end_effector->position - truth.end_effector->top_centre;
    score.end_effector_error_m = std::sqrt(error.dot(error));
  }
  return score;
}

void ScoreSummary::add(const FrameScore& score) {
  true_positives += score.true_positives;
  false_positives += score.false_positives;
  false_negatives += score.false_negatives;
  errors_3d_m.insert(errors_3d_m.end(), score.errors_3d_m.begin(), score.errors_3d_m.end());
  centre_errors_3d_m.insert(centre_errors_3d_m.end(), score.centre_errors_3d_m.begin(), score.centre_errors_3d_m.end());
  end_effector_expected += score.end_effector_expected;
  end_effector_found += score.end_effector_expected && score.end_effector_found;
  end_effector_false += score.end_effector_false;
  if (score.end_effector_expected && score.end_effector_located)
    end_effector_errors_m.push_back(score.end_effector_error_m);
}

double ScoreSummary::precision() const {
  const int detected = true_positives + false_positives;
  return detected > 0 ? double(true_positives) / detected : 1.0;
}

double ScoreSummary::recall() const {
  const int present = true_positives + false_negatives;
  return present > 0 ? double(true_positives) / present : 1.0;
}

double ScoreSummary::meanError3d() const {
  if (errors_3d_m.empty()) return 0.0;
  return std::accumulate(errors_3d_m.begin(), errors_3d_m.end(), 0.0) / errors_3d_m.size();
}

double ScoreSummary::percentileError3d(double q) const {
  if (errors_3d_m.empty()) return 0.0;
  std::vector<double> sorted = errors_3d_m;
  std::sort(sorted.begin(), sorted.end());
  const size_t index = std::min(sorted.size() - 1, static_cast<size_t>(std::floor(q * (sorted.size() - 1) + 0.5)));
  return sorted[index];
}

}  // namespace perception
}  // namespace cotton_harvester
