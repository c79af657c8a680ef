#include "cotton_harvester/control/harvest_decision.h"

#include <cmath>

namespace cotton_harvester {
namespace control {

const char* toString(HarvestAction action) {
  switch (action) {
    case HarvestAction::kForward:
      return "forward";
    case HarvestAction::kBackward:
      return "backward";
    case HarvestAction::kArmUp:
      return "arm_up";
    case HarvestAction::kArmDown:
      return "arm_down";
    case HarvestAction::kPick:
      return "pick";
    case HarvestAction::kPassOn:
      return "pass_on";
    case HarvestAction::kOutOfReach:
      return "out_of_reach";
  }
  return "unknown";
}

std::string DecisionParams::check() const {
  if (!(y_tolerance_m > 0.0)) return "y_tolerance_m: expected > 0";
  if (!(z_tolerance_m > 0.0)) return "z_tolerance_m: expected > 0";
  if (!(pick_reach_m > 0.0)) return "pick_reach_m: expected > 0 (paper: 0.37)";
  if (!(y_forward_sign == 1.0 || y_forward_sign == -1.0)) return "y_forward_sign: expected 1 or -1";
  return "";
}

HarvestDecision decide(const Point3& boll, const Point3& end_effector, const DecisionParams& params) {
  HarvestDecision decision;
  const double dy = boll.y - end_effector.y;
  if (std::abs(dy) > params.y_tolerance_m) {
    decision.action = dy > 0.0 ? HarvestAction::kForward : HarvestAction::kBackward;
    decision.rover_move_m = params.y_forward_sign * dy;
    return decision;
  }
  const double dz = boll.z - end_effector.z;
  if (std::abs(dz) > params.z_tolerance_m) {
    // Zm > Zb: the end effector is deeper (further from the camera) than the boll: go up.
    decision.action = dz < 0.0 ? HarvestAction::kArmUp : HarvestAction::kArmDown;
    decision.arm_depth_m = boll.z;
    return decision;
  }
  decision.pick_offset_m = boll.x - end_effector.x;
  decision.action =
      std::abs(end_effector.x - boll.x) < params.pick_reach_m ? HarvestAction::kPick : HarvestAction::kOutOfReach;
  return decision;
}

}  // namespace control
}  // namespace cotton_harvester
