#pragma once

#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <thorvald_state_machine/state_machine.h>

#include "cotton_harvester/control/boll_tracker.h"
#include "cotton_harvester/control/harvest_actions.h"
#include "cotton_harvester/control/harvest_decision.h"
#include "cotton_harvester/control/harvest_metrics.h"
#include "cotton_harvester/control/harvest_plant.h"

namespace cotton_harvester {
namespace control {

struct HarvestParams {
  DecisionParams decision;
  TrackerParams tracker;
  double max_rover_step_m = 0.5;     ///< a forward/backward move is clamped to this
  double pass_step_m = 0.3;          ///< "pass on": rover step when no pickable boll is seen
  double row_length_m = 5.3;         ///< the run ends after this much travel (paper's field tests: 5.3 m)
  int max_missed_observations = 10;  ///< frames in a row without an end effector or at all: abort
  int max_failed_actions = 3;        ///< rover/arm failures in a row: abort
  int bolls_present = 0;             ///< ground truth for the metrics, 0 when unknown
  /// A boll being worked on that a frame does not show (a leaf hides it from straight above once the rover stands
  /// over it) is still aimed at from where the tracker last saw it, for this many frames after its last
  /// sighting; 0: only what the frame shows (the paper's Algorithm 1).
  int remember_target_frames = 0;
  /// The boll being worked on stays the target until it is picked or skipped, whichever boll the order would pick
  /// in a frame (seen, or remembered as above); without it a boll that a frame does not show, or that the order
  /// ranks behind another after the rover moved, makes the rover turn to the other one and back. With
  /// remember_target_frames 0 it is kept only while frames show it. false: a new choice in every frame (Algorithm 1).
  bool keep_target = false;
  /// Before passing on: a pending boll that earlier frames showed reachable (at least twice) but this one does not
  /// (hidden from where the camera now stands), within revisit_window_m behind or ahead of the camera, is aimed at
  /// from the tracker's memory, the rearmost first. false: only what the frame shows or the target's memory.
  bool revisit_pending = false;
  double revisit_window_m = 1.0;  ///< [m] along the row
  /// Before the rover moves on (passing on, or forward to a boll) from a place of the row not searched yet (no
  /// search within search_spacing_m / 2), the SEARCH_LEAVES state asks the plant to look under the leaves there
  /// (HarvestPlant::searchUnderLeaves), then observes again; forward moves are then at most search_spacing_m. For
  /// undefoliated cotton, where leaves hide bolls from the camera everywhere on the row. false: pass on at once (the
  /// paper's Algorithm 1).
  bool search_under_leaves = false;
  double search_spacing_m = 0.2;  ///< [m] along the row
  /// How the rover's arm picks, clears leaves, looks under them and rests (the manoeuvres, HarvestActions).
  HarvestActionParams actions;
  std::string check() const;  ///< empty when sound, otherwise "key: expected ..."
};

/// The harvest state machine (paper §2.9, Algorithm 1, Figures 13–14) on thorvald_state_machine:
/// OBSERVE (state 0) decides from the nearest reachable pending boll and the end effector and goes
/// to MOVE_FORWARD, MOVE_BACKWARD, ARM_UP, ARM_DOWN, PICK or PASS_ON; every one of them returns to
/// OBSERVE. Failed picks are retried up to max_pick_attempts, then the boll is skipped and counted.
/// Outcomes: "finished" (row done), "aborted" (no frames, or actions keep failing), "preempted". The moves, the pick
/// and the search under the leaves are HarvestActions on the plant's primitives.
class HarvestMachine {
 public:
  /// Throws std::invalid_argument naming the key when params.actions are not sound.
  HarvestMachine(HarvestPlant& plant, const HarvestParams& params);

  /// Runs the machine (blocking) and returns its outcome.
  std::string run();
  /// Counts of the run so far (thread-safe).
  HarvestCounts counts() const;
  /// The bolls of the run so far and their fates (thread-safe copy).
  std::vector<TrackedBoll> tracks() const;
  thorvald_state_machine::StateMachine& machine() { return *machine_; }
  /// The manoeuvres the machine runs (their counters: picks that cleared leaves, searches under the leaves).
  const HarvestActions& actions() const { return actions_; }
  /// The boll (camera frame, from the frame it was chosen in) and the end effector of the last decision.
  std::optional<std::pair<Point3, Point3>> lastDecisionPoints() const;
  /// Sightings that could not be used: bolls without an end effector in the frame, NaN points.
  int rejectedFrames() const;
  /// Why the last run aborted (frames missing or without an end effector, or actions failing, with the plant's
  /// last failure); empty unless it did.
  std::string abortReason() const;

 private:
  std::string observe(thorvald_state_machine::UserData& ud, thorvald_state_machine::ExecutionContext& ctx);
  std::string act(HarvestAction action, thorvald_state_machine::UserData& ud,
                  thorvald_state_machine::ExecutionContext& ctx);
  std::string passOn(thorvald_state_machine::ExecutionContext& ctx);
  std::string searchLeaves(thorvald_state_machine::ExecutionContext& ctx);
  /// search_under_leaves: this place of the row has not been searched yet.
  bool searchDue() const;
  std::string resultOutcome(MoveResult result);
  /// A frame that could not be used (mutex held): "retry", or "lost" after max_missed_observations in a row.
  std::string missedObservation(const std::string& why);
  /// The target boll from the tracker's memory (camera frame at the frame's rover position), when it may be used.
  std::optional<Point3> rememberedTarget(const HarvestObservation& observation) const;
  /// revisit_pending: the rearmost pending boll hidden in this frame (its id in *id), in the camera frame.
  std::optional<Point3> revisitTarget(const HarvestObservation& observation, const std::vector<int>& ids,
                                      int* id) const;
  /// The target boll while it is pending: its sighting in the frame, else rememberedTarget().
  std::optional<Point3> keptTarget(const HarvestObservation& observation, const std::vector<int>& ids) const;

  HarvestPlant& plant_;
  HarvestParams params_;
  HarvestActions actions_;
  std::unique_ptr<thorvald_state_machine::StateMachine> machine_;
  mutable std::mutex mutex_;
  BollTracker tracker_;
  double start_time_s_ = 0.0;
  double start_position_m_ = 0.0;
  double last_position_m_ = 0.0;
  double last_time_s_ = 0.0;
  int missed_ = 0;
  int failed_actions_ = 0;
  int rejected_frames_ = 0;
  HarvestDecision decision_;
  int target_id_ = 0;
  std::optional<std::pair<Point3, Point3>> decision_points_;
  std::vector<double> searched_m_;  ///< rover positions where the leaves were searched
  std::string abort_reason_;
};

}  // namespace control
}  // namespace cotton_harvester
