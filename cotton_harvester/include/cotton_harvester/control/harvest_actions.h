#pragma once

#include <atomic>
#include <cstddef>
#include <optional>
#include <string>

#include "cotton_harvester/control/canopy_search.h"
#include "cotton_harvester/control/harvest_plant.h"
#include "cotton_harvester/control/leaf_clearance.h"

namespace cotton_harvester {
namespace control {

/// How the rover's arm harvests: the pick, clearing leaves before it, the search under the leaves and where the arm
/// rests. One set of defaults for the robot's node (harvest_state_machine: the keys named in check()) and the
/// in-process simulation (harvest_bench, mujoco_harvest). Where the node's plant and the simulator's used to
/// differ, the simulator's behaviour (what harvest_bench measured) was kept:
/// - the arm returns to its rest extension after a pick, before a search and after it, and while the rover drives
///   (it went back to where it started the pick, and stayed there while driving, on the node);
/// - going up to rest_depth_m as the rover starts and before a search happens only from deeper (the node went to
///   rest_depth_m from above too before a search);
/// - the strip searched under the leaves is the arm's plane, arm.strip_y_m (the simulator used y = 0 whatever the
///   calibration said).
struct HarvestActionParams {
  ArmWorkspace arm;           ///< the arm's calibration, travel and rest
  double pick_dwell_s = 1.0;  ///< [s] the vacuum runs this long at the boll before the arm retracts
  /// The vacuum stays on while the arm retracts from the boll (a boll caught late still follows the nozzle);
  /// false: off at the boll.
  bool vacuum_while_retracting = true;
  /// After a pick the arm also goes up to arm.rest_depth_m at once; false: it stays at the boll's depth for the next
  /// boll of the same stop and goes up only when the rover moves.
  bool raise_after_pick = false;
  /// Before a pick, when the cloud of the frame the decision used shows leaves over the boll along the approach,
  /// the arm sweeps them aside and a new frame locates the boll again (LeafClearanceParams). Off by default (the
  /// paper's pick, what the robot's config runs; measured no better through the nodes, README); the simulated
  /// experiments (pottedConfig, fieldConfig) turn it on, as harvest_bench always measured.
  bool clear_leaves_before_pick = false;
  LeafClearanceParams leaves;
  /// Looking under the leaves when the machine asks (HarvestParams::search_under_leaves); needs arm.rest_depth_m.
  CanopySearchParams canopy;
  std::string check() const;  ///< empty when sound, otherwise "key: expected ..." (the node's parameter names)
};

/// The harvest manoeuvres, once, on the plant's primitives: the machine's rover and arm moves, the pick (with the
/// leaf clearing before it), the search under the leaves. The same code runs on the robot (TopicHarvestPlant) and
/// in harvest_bench (SimHarvestPlant). Not thread-safe except for the counters.
class HarvestActions {
 public:
  using Preempted = HarvestPlant::Preempted;
  /// Throws std::invalid_argument naming the key when `params` are not sound.
  HarvestActions(HarvestPlant& plant, const HarvestActionParams& params);

  /// The rover moves by `distance_m` (NaN: failed) with the arm going to its rest meanwhile (restPose()).
  MoveResult moveRover(double distance_m, const Preempted& preempted);
  /// The vertical axis to `depth_m`, clamped into the arm's travel (NaN: failed).
  MoveResult armToDepth(double depth_m, const Preempted& preempted);
  /// The pick: leaves over the boll swept aside first (clear_leaves_before_pick), the horizontal axis out by
  /// `offset_m` (clamped into the travel), vacuum on for pick_dwell_s, back to the rest extension, vacuum off.
  MoveResult pick(double offset_m, const Preempted& preempted);
  /// Looks under the leaves in the arm's strip: the arm to its rest, a frame, then up to canopy.max_passes sweeps
  /// through the shallowest layer of foliage left (CanopySearch), a frame after each; the arm back to its rest
  /// extension. kDone when it swept, nullopt when the strip held nothing to sweep.
  std::optional<MoveResult> searchUnderLeaves(const Preempted& preempted);

  /// Where the arm rests from where it is: the rest extension, and the rest depth when it is deeper (NaN: stays).
  ArmPose restPose() const;
  const HarvestActionParams& params() const { return params_; }

  /// Picks that swept leaves aside first, and of them those whose target a new frame corrected.
  int picksCleared() const { return picks_cleared_; }
  int picksRedetected() const { return picks_redetected_; }
  /// Places of the row where the arm looked under the leaves, and its sweeps there.
  int leafSearches() const { return leaf_searches_; }
  int leafSweeps() const { return leaf_sweeps_; }

 private:
  double clampExtension(double extension_m) const;
  double clampDepth(double depth_m) const;
  /// Points over the approach from the arm at `from` to camera x `target_x` in the last frame's cloud.
  int leafPointsOver(const ArmPose& from, double target_x, const Preempted& preempted);
  /// Sweeps the leaves over the target at camera x *target_x aside and moves *target_x to the boll a new frame
  /// shows nearest it (the arm goes to that boll's depth when it differs).
  MoveResult clearLeaves(const ArmPose& from, double* target_x, const Preempted& preempted);
  /// The arm's moves one after another, stopping at the first that is not done.
  template <std::size_t N>
  MoveResult moveArmThrough(const ArmPose (&poses)[N], const Preempted& preempted);

  HarvestPlant& plant_;
  HarvestActionParams params_;
  std::atomic<int> picks_cleared_{0}, picks_redetected_{0}, leaf_searches_{0}, leaf_sweeps_{0};
};

}  // namespace control
}  // namespace cotton_harvester
