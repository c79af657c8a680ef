#include "cotton_harvester_sim/miss_causes.h"

#include <cmath>

namespace cotton_harvester {
namespace sim {

const char* toString(MissCause cause) {
  switch (cause) {
    case MissCause::kCaptured:
      return "captured";
    case MissCause::kOutOfWorkspace:
      return "out_of_workspace";
    case MissCause::kNeverInView:
      return "never_in_view";
    case MissCause::kHiddenFromRow:
      return "hidden_from_row";
    case MissCause::kOccluded:
      return "occluded";
    case MissCause::kNotDetected:
      return "not_detected";
    case MissCause::kJudgedUnreachable:
      return "judged_unreachable";
    case MissCause::kPassedOver:
      return "passed_over";
    case MissCause::kAlignGaveUp:
      return "align_gave_up";
    case MissCause::kJudgedOutOfReach:
      return "judged_out_of_reach";
    case MissCause::kPicksFailed:
      return "picks_failed";
    case MissCause::kBelievedPicked:
      return "believed_picked";
    case MissCause::kCount:
      break;
  }
  return "unknown";
}

MissCause classifyMiss(const BollRecord& boll, const std::vector<control::TrackedBoll>& tracks,
                       const control::TrackerParams& tracker) {
  if (boll.captured) return MissCause::kCaptured;
  if (!boll.reachable) return MissCause::kOutOfWorkspace;
  if (boll.frames_in_view == 0) return MissCause::kNeverInView;
  if (boll.frames_detected == 0 && boll.row_best_visible_fraction < 0.5) return MissCause::kHiddenFromRow;
  if (boll.frames_detected == 0)
    return boll.max_visible_fraction < 0.5 ? MissCause::kOccluded : MissCause::kNotDetected;
  if (boll.frames_detected_reachable == 0 || !boll.sighted) return MissCause::kJudgedUnreachable;
  const control::TrackedBoll* track = nullptr;
  double best = tracker.match_radius_m;
  for (const auto& t : tracks) {
    const double d = std::hypot(t.along_row_m - boll.along_row_m, t.across_m - boll.across_m, t.depth_m - boll.depth_m);
    if (d <= best) {
      best = d;
      track = &t;
    }
  }
  if (!track) return MissCause::kJudgedUnreachable;
  switch (track->fate) {
    case control::BollFate::kPending:
      return MissCause::kPassedOver;
    case control::BollFate::kPicked:
      return MissCause::kBelievedPicked;
    case control::BollFate::kSkipped:
    default:
      if (track->pick_attempts >= tracker.max_pick_attempts) return MissCause::kPicksFailed;
      if (track->align_moves > tracker.max_align_moves) return MissCause::kAlignGaveUp;
      return MissCause::kJudgedOutOfReach;
  }
}

void MissTable::add(const MissTable& other) {
  for (size_t i = 0; i < count.size(); ++i) count[i] += other.count[i];
}

int MissTable::misses() const {
  int n = 0;
  for (size_t i = 1; i < count.size(); ++i) n += count[i];
  return n;
}

}  // namespace sim
}  // namespace cotton_harvester
