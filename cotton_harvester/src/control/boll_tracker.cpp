#include "cotton_harvester/control/boll_tracker.h"

#include <cmath>
#include <limits>

namespace cotton_harvester {
namespace control {

std::vector<int> BollTracker::update(const HarvestObservation& observation) {
  ++frame_;
  std::vector<int> ids(observation.bolls.size(), 0);
  std::vector<bool> taken(tracks_.size(), false);
  for (std::size_t i = 0; i < observation.bolls.size(); ++i) {
    const Point3& p = observation.bolls[i].position;
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) continue;
    const double along = observation.rover_position_m + params_.y_forward_sign * p.y;
    double best = params_.match_radius_m;
    std::size_t best_track = tracks_.size();
    for (std::size_t t = 0; t < tracks_.size(); ++t) {
      if (taken[t]) continue;
      const double d = std::hypot(tracks_[t].along_row_m - along, tracks_[t].across_m - p.x, tracks_[t].depth_m - p.z);
      if (d <= best) {
        best = d;
        best_track = t;
      }
    }
    if (best_track == tracks_.size()) {
      TrackedBoll track;
      track.id = next_id_++;
      tracks_.push_back(track);
      taken.push_back(false);
    }
    TrackedBoll& track = tracks_[best_track];
    taken[best_track] = true;
    track.along_row_m = along;
    track.across_m = p.x;
    track.depth_m = p.z;
    track.last_seen_frame = frame_;
    ++track.sightings;
    track.seen_reachable = track.seen_reachable || observation.bolls[i].reachable;
    ids[i] = track.id;
  }
  if (pending_pick_) {
    if (TrackedBoll* track = findMutable(*pending_pick_)) {
      if (track->last_seen_frame == frame_) {
        if (track->pick_attempts >= params_.max_pick_attempts) track->fate = BollFate::kSkipped;
      } else {
        track->fate = BollFate::kPicked;
      }
    }
    pending_pick_.reset();
  }
  return ids;
}

std::optional<std::size_t> BollTracker::nearestPending(const HarvestObservation& observation,
                                                       const std::vector<int>& ids) const {
  std::optional<std::size_t> best;
  double best_along = std::numeric_limits<double>::infinity();
  double best_distance = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < observation.bolls.size() && i < ids.size(); ++i) {
    const BollSighting& boll = observation.bolls[i];
    const TrackedBoll* track = find(ids[i]);
    if (!boll.reachable || track == nullptr || track->fate != BollFate::kPending) continue;
    const double distance = std::sqrt(boll.position.x * boll.position.x + boll.position.y * boll.position.y +
                                      boll.position.z * boll.position.z);  // eq. 6
    bool better = distance < best_distance;
    if (params_.order == TargetOrder::kAlongRow) {
      const double along = params_.y_forward_sign * boll.position.y;
      if (along < best_along - params_.along_row_band_m)
        better = true;
      else if (along > best_along + params_.along_row_band_m)
        better = false;
      if (better) best_along = along;
    }
    if (better) {
      best_distance = distance;
      best = i;
    }
  }
  return best;
}

void BollTracker::notePick(int id) {
  if (TrackedBoll* track = findMutable(id)) {
    ++track->pick_attempts;
    track->reached = true;
    pending_pick_ = id;
  }
}

void BollTracker::noteAlignMove(int id) {
  if (TrackedBoll* track = findMutable(id)) {
    if (++track->align_moves > params_.max_align_moves) track->fate = BollFate::kSkipped;
  }
}

void BollTracker::skip(int id) {
  if (TrackedBoll* track = findMutable(id)) track->fate = BollFate::kSkipped;
}

const TrackedBoll* BollTracker::find(int id) const {
  for (const auto& track : tracks_)
    if (track.id == id) return &track;
  return nullptr;
}

TrackedBoll* BollTracker::findMutable(int id) {
  for (auto& track : tracks_)
    if (track.id == id) return &track;
  return nullptr;
}

int BollTracker::reached() const {
  int n = 0;
  for (const auto& t : tracks_) n += t.reached ? 1 : 0;
  return n;
}

int BollTracker::picked() const {
  int n = 0;
  for (const auto& t : tracks_) n += t.fate == BollFate::kPicked ? 1 : 0;
  return n;
}

int BollTracker::skipped() const {
  int n = 0;
  for (const auto& t : tracks_) n += t.fate == BollFate::kSkipped ? 1 : 0;
  return n;
}

int BollTracker::pickAttempts() const {
  int n = 0;
  for (const auto& t : tracks_) n += t.pick_attempts;
  return n;
}

}  // namespace control
}  // namespace cotton_harvester
