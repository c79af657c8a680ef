#pragma once

#include <optional>
#include <vector>

#include "cotton_harvester/control/harvest_decision.h"

namespace cotton_harvester {
namespace control {

/// Fate of one boll during a run.
enum class BollFate { kPending, kPicked, kSkipped };

/// One boll seen during a run, kept in row coordinates so it is recognised after the rover moved.
struct TrackedBoll {
  int id = 0;
  double along_row_m = 0.0;  ///< rover position + y_forward_sign × camera y
  double across_m = 0.0;     ///< camera x
  double depth_m = 0.0;      ///< camera z
  int pick_attempts = 0;     ///< picks tried on it
  int align_moves = 0;       ///< rover and arm moves made towards it
  bool reached = false;      ///< the arm got to it and tried a pick
  BollFate fate = BollFate::kPending;
  int last_seen_frame = 0;
  int sightings = 0;            ///< frames that showed it
  bool seen_reachable = false;  ///< some frame showed it inside the arm's workspace
};

/// Which pending boll is worked on next.
enum class TargetOrder {
  kRange,    ///< the nearest from the lens (eq. 6, Algorithm 1 step 6): high bolls first, wherever they are
  kAlongRow  ///< the rearmost along the row (a sweep in the direction of travel), then the nearest from the lens
};

struct TrackerParams {
  double match_radius_m = 0.06;  ///< a sighting within this of a track is that boll
  int max_pick_attempts = 3;     ///< failed picks before the boll is skipped
  int max_align_moves = 8;       ///< moves towards one boll before it is skipped
  double y_forward_sign = 1.0;
  TargetOrder order = TargetOrder::kRange;
  /// kAlongRow: bolls whose along-row positions differ by less than this are one stop of the rover and are taken
  /// nearest from the lens first [m].
  double along_row_band_m = 0.03;
};

/// Remembers the bolls of a run: associates sightings with tracks, counts attempts, decides
/// whether a pick worked (the boll is gone from the next frame), and skips bolls that used up
/// their retries. Counts feed the harvest metrics.
class BollTracker {
 public:
  explicit BollTracker(const TrackerParams& params = TrackerParams()) : params_(params) {}

  /// Associates the frame's sightings with tracks (new ones are created). Returns, per sighting,
  /// the track id. A pick in progress is resolved: picked if its boll is not seen, else a failed
  /// attempt (skipped after max_pick_attempts).
  std::vector<int> update(const HarvestObservation& observation);

  /// The next reachable sighting whose boll is still pending, in `order` (kRange: the smallest distance from the
  /// camera, eq. 6); its index in the observation, or nullopt.
  std::optional<std::size_t> nearestPending(const HarvestObservation& observation, const std::vector<int>& ids) const;

  void notePick(int id);       ///< a pick was made on this boll: resolve it on the next frame
  void noteAlignMove(int id);  ///< a move towards it; skips it after max_align_moves
  void skip(int id);           ///< out of reach, or given up

  const std::vector<TrackedBoll>& tracks() const { return tracks_; }
  const TrackedBoll* find(int id) const;
  /// Frames seen so far (TrackedBoll::last_seen_frame counts the same way).
  int frame() const { return frame_; }
  int detected() const { return static_cast<int>(tracks_.size()); }
  int reached() const;
  int picked() const;
  int skipped() const;
  int pickAttempts() const;

 private:
  TrackedBoll* findMutable(int id);
  TrackerParams params_;
  std::vector<TrackedBoll> tracks_;
  std::optional<int> pending_pick_;
  int frame_ = 0;
  int next_id_ = 1;
};

}  // namespace control
}  // namespace cotton_harvester
