#include "cotton_harvester/control/harvest_actions.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace cotton_harvester {
namespace control {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
/// A boll re-located this much deeper or shallower after the leaf clearing: the housing goes to its top [m] (a boll
/// seen only at its side past the leaf was located deeper than its top).
constexpr double kRedetectDepthStepM = 0.015;

bool finite(double v) { return std::isfinite(v); }

std::string checkArm(const ArmWorkspace& a) {
  if (!finite(a.extension_zero_x_m)) return "arm_extension_zero_x_m: expected a finite number";
  if (!finite(a.strip_y_m)) return "arm_y_m: expected a finite number";
  if (!(a.extension_min_m >= 0.0 && a.extension_min_m < a.extension_max_m && finite(a.extension_max_m)))
    return "horizontal_min_m, horizontal_max_m: expected 0 <= min < max";
  if (!(a.min_depth_m >= 0.0 && a.min_depth_m < a.max_depth_m && finite(a.max_depth_m)))
    return "vertical_min_m, vertical_max_m: expected 0 <= min < max";
  if (!(a.rest_extension_m >= a.extension_min_m && a.rest_extension_m <= a.extension_max_m))
    return "rest_extension_m: expected within [horizontal_min_m, horizontal_max_m]";
  if (!(a.rest_depth_m == 0.0 || (a.rest_depth_m >= a.min_depth_m && a.rest_depth_m <= a.max_depth_m)))
    return "rest_depth_m: expected 0 (none) or within [vertical_min_m, vertical_max_m]";
  return "";
}

}  // namespace

std::string HarvestActionParams::check() const {
  if (auto bad = checkArm(arm); !bad.empty()) return bad;
  if (!(pick_dwell_s > 0.0) || !finite(pick_dwell_s)) return "pick_dwell_s: expected > 0";
  if (auto bad = leaves.check(); !bad.empty()) return bad;
  if (auto bad = canopy.check(); !bad.empty()) return "search_" + bad;
  if (leaves.effector_half_m != canopy.effector_half_m)
    return "effector_half_m: expected one housing for the leaf clearing and the search";
  return "";
}

HarvestActions::HarvestActions(HarvestPlant& plant, const HarvestActionParams& params)
    : plant_(plant), params_(params) {
  if (auto bad = params_.check(); !bad.empty()) throw std::invalid_argument("harvest actions: " + bad);
}

double HarvestActions::clampExtension(double extension_m) const {
  return std::clamp(extension_m, params_.arm.extension_min_m, params_.arm.extension_max_m);
}

double HarvestActions::clampDepth(double depth_m) const {
  return std::clamp(depth_m, params_.arm.min_depth_m, params_.arm.max_depth_m);
}

ArmPose HarvestActions::restPose() const {
  ArmPose pose;
  pose.extension_m = params_.arm.rest_extension_m;
  const double rest = params_.arm.rest_depth_m;
  const auto now = plant_.armPose();
  if (rest > 0.0 && now && now->depth_m > rest) pose.depth_m = rest;
  return pose;
}

template <std::size_t N>
MoveResult HarvestActions::moveArmThrough(const ArmPose (&poses)[N], const Preempted& preempted) {
  for (const ArmPose& pose : poses)
    if (const MoveResult r = plant_.moveArm(pose, preempted); r != MoveResult::kDone) return r;
  return MoveResult::kDone;
}

MoveResult HarvestActions::moveRover(double distance_m, const Preempted& preempted) {
  if (!finite(distance_m)) return MoveResult::kFailed;
  // Drive with the arm at its rest, clear of the plants: the axes move while the rover starts.
  return plant_.moveRover(distance_m, restPose(), preempted);
}

MoveResult HarvestActions::armToDepth(double depth_m, const Preempted& preempted) {
  if (!finite(depth_m)) return MoveResult::kFailed;
  return plant_.moveArm(ArmPose{kNaN, clampDepth(depth_m)}, preempted);
}

int HarvestActions::leafPointsOver(const ArmPose& from, double target_x, const Preempted& preempted) {
  const auto cloud = plant_.lastCloud(preempted);
  if (!cloud) return 0;
  return pointsOverApproach(cloud->view, from.extension_m + params_.arm.extension_zero_x_m, target_x, from.depth_m,
                            params_.leaves);
}

MoveResult HarvestActions::clearLeaves(const ArmPose& from, double* target_x, const Preempted& preempted) {
  const LeafClearanceParams& p = params_.leaves;
  const double depth = from.depth_m;
  const double target_ext = *target_x - params_.arm.extension_zero_x_m;
  const double dir = target_ext >= from.extension_m ? 1.0 : -1.0;
  ++picks_cleared_;
  // Up to the leaf's level, through it past the boll, back off, down to the boll's top again.
  const ArmPose sweep[] = {{kNaN, clampDepth(depth - p.leaf_clearance_m)},
                           {clampExtension(target_ext + dir * p.clear_overshoot_m), kNaN},
                           {clampExtension(target_ext - dir * p.clear_standoff_m), kNaN},
                           {kNaN, depth}};
  if (const MoveResult r = moveArmThrough(sweep, preempted); r != MoveResult::kDone) return r;
  // Look again: the boll in full view is located on its whole top rather than on the part past the leaf. Without a
  // frame the pick goes where it was aimed.
  const auto seen = plant_.observe(preempted);
  if (!seen) return MoveResult::kDone;
  double best = p.redetect_radius_m, corrected = *target_x, corrected_depth = depth;
  for (const auto& b : seen->bolls) {
    const double d = std::hypot(b.position.x - *target_x, b.position.y, b.position.z - depth);
    if (d < best) {
      best = d;
      corrected = b.position.x;
      corrected_depth = b.position.z;
    }
  }
  if (!(best < p.redetect_radius_m)) return MoveResult::kDone;
  ++picks_redetected_;
  *target_x = corrected;
  if (std::abs(corrected_depth - depth) <= kRedetectDepthStepM) return MoveResult::kDone;
  return plant_.moveArm(ArmPose{kNaN, clampDepth(corrected_depth)}, preempted);
}

MoveResult HarvestActions::pick(double offset_m, const Preempted& preempted) {
  if (!finite(offset_m)) return MoveResult::kFailed;
  const auto from = plant_.armPose();
  if (!from || !finite(from->extension_m)) return MoveResult::kFailed;
  const double zero = params_.arm.extension_zero_x_m;
  double target_x = from->extension_m + zero + offset_m;  // camera x of the boll
  if (params_.clear_leaves_before_pick && finite(from->depth_m) &&
      leafPointsOver(*from, target_x, preempted) >= params_.leaves.leaf_points_min) {
    if (const MoveResult r = clearLeaves(*from, &target_x, preempted); r != MoveResult::kDone) return r;
  }
  if (const MoveResult r = plant_.moveArm(ArmPose{clampExtension(target_x - zero), kNaN}, preempted);
      r != MoveResult::kDone)
    return r;
  plant_.setVacuum(true);
  if (plant_.wait(params_.pick_dwell_s, preempted) == MoveResult::kPreempted) {
    plant_.setVacuum(false);
    return MoveResult::kPreempted;
  }
  if (!params_.vacuum_while_retracting) plant_.setVacuum(false);
  const MoveResult back = plant_.moveArm(ArmPose{params_.arm.rest_extension_m, kNaN}, preempted);
  if (params_.vacuum_while_retracting) plant_.setVacuum(false);
  if (back != MoveResult::kDone || !params_.raise_after_pick || !(params_.arm.rest_depth_m > 0.0)) return back;
  return plant_.moveArm(ArmPose{kNaN, params_.arm.rest_depth_m}, preempted);
}

std::optional<MoveResult> HarvestActions::searchUnderLeaves(const Preempted& preempted) {
  const ArmWorkspace& arm = params_.arm;
  if (!(arm.rest_depth_m > 0.0)) return std::nullopt;  // no rest above the plants to look from
  const auto stopped = [&] { return preempted() ? MoveResult::kPreempted : MoveResult::kFailed; };
  // The housing above the plants at its rest, then a frame: everything deeper than the housing is the canopy.
  if (const MoveResult r = plant_.moveArm(restPose(), preempted); r != MoveResult::kDone) return r;
  if (!plant_.observe(preempted)) return stopped();
  ++leaf_searches_;
  CanopySearch search(arm, params_.canopy);
  int passes = 0;
  for (int pass = 0; pass < params_.canopy.max_passes; ++pass) {
    const auto cloud = plant_.lastCloud(preempted);
    if (preempted()) return MoveResult::kPreempted;
    if (!cloud || !(cloud->fx_px > 0.0)) break;
    const auto sweep = search.next(cloud->view, cloud->fx_px);
    if (!sweep) break;
    // Beside the layer above the plants, down (a vertical move pushes no leaf), through it, up again.
    const ArmPose moves[] = {{sweep->from_extension_m, kNaN},
                             {kNaN, sweep->depth_m},
                             {sweep->to_extension_m, kNaN},
                             {kNaN, arm.rest_depth_m}};
    if (const MoveResult r = moveArmThrough(moves, preempted); r != MoveResult::kDone) return r;
    ++passes;
    ++leaf_sweeps_;
    if (pass + 1 < params_.canopy.max_passes && !plant_.observe(preempted)) {
      if (preempted()) return MoveResult::kPreempted;
      break;
    }
  }
  if (const MoveResult r = plant_.moveArm(ArmPose{arm.rest_extension_m, kNaN}, preempted); r != MoveResult::kDone)
    return r;
  if (passes == 0) return std::nullopt;
  return MoveResult::kDone;
}

}  // namespace control
}  // namespace cotton_harvester
