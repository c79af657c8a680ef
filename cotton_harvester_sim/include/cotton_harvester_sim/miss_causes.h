#pragma once

#include <array>
#include <limits>
#include <string>
#include <vector>

#include "cotton_harvester/control/boll_tracker.h"

namespace cotton_harvester {
namespace sim {

/// Why a boll present in the row was not taken by the vacuum (scoring only: it reads the simulation's truth).
enum class MissCause {
  kCaptured = 0,       ///< not a miss
  kOutOfWorkspace,     ///< truth: outside the arm's workspace along the driven stretch
  kNeverInView,        ///< the camera never had it in its image
  kHiddenFromRow,      ///< never detected, and no camera position along the row sees half of it (leaves as grown)
  kOccluded,           ///< in view, never detected, and never more than half visible from the camera (leaves, arm)
  kNotDetected,        ///< in view and at least half visible in some frame, but never detected
  kJudgedUnreachable,  ///< detected, but perception never flagged it reachable, or no track held it
  kPassedOver,         ///< tracked and still pending when the rover drove on or the row ended
  kAlignGaveUp,        ///< skipped after max_align_moves rover/arm moves towards it
  kJudgedOutOfReach,   ///< skipped: aligned, but the arm's horizontal reach was judged too short
  kPicksFailed,        ///< picks tried; after max_pick_attempts it was still seen, and skipped
  kBelievedPicked,     ///< the machine took it for picked (gone from the next frame) but the vacuum never took it
  kCount
};
const char* toString(MissCause cause);

/// What the scorer saw of one boll during a run.
struct BollRecord {
  bool captured = false;
  bool reachable = false;   ///< truth: inside the workspace along the driven stretch
  int frames_in_view = 0;   ///< frames whose image held its centre
  int frames_detected = 0;  ///< frames with a detection within match_radius_m of its visible top
  int frames_detected_reachable = 0;
  double max_visible_fraction = 0.0;  ///< largest share of the rays to it that reached it first
  /// The same share's largest value over every camera position along the driven row at the start of the run (the
  /// leaves as they grew), whether or not the camera stood there; 1 when not computed.
  double row_best_visible_fraction = 1.0;
  bool sighted = false;  ///< its last sighting, in the tracker's row coordinates:
  double along_row_m = 0.0, across_m = 0.0, depth_m = 0.0;
  /// Closest approach of the nozzle to its centre while the vacuum ran [m]; infinity when never.
  double closest_vacuum_m = std::numeric_limits<double>::infinity();
};

/// Classifies one boll from what the scorer saw and the tracker's tracks at the end of the run. A track is the
/// boll's when it lies within `match_radius_m` of the boll's last sighting (row coordinates, as BollTracker keeps
/// them).
MissCause classifyMiss(const BollRecord& boll, const std::vector<control::TrackedBoll>& tracks,
                       const control::TrackerParams& tracker);

/// Miss causes counted over bolls.
struct MissTable {
  std::array<int, static_cast<int>(MissCause::kCount)> count{};
  void add(MissCause cause) { ++count[static_cast<int>(cause)]; }
  void add(const MissTable& other);
  int misses() const;  ///< every cause but kCaptured
};

}  // namespace sim
}  // namespace cotton_harvester
