#pragma once

#include <optional>
#include <string>
#include <vector>

namespace cotton_harvester {
namespace control {

/// A point in the camera frame [m]: x across the row (the horizontal arm's axis), y along the row,
/// z the depth from the camera (it looks down).
struct Point3 {
  double x = 0.0, y = 0.0, z = 0.0;
};

/// One boll as perception reports it.
struct BollSighting {
  Point3 position;
  double confidence = 0.0;
  bool reachable = false;
};

/// Everything state 0 of the harvest machine gets from one camera frame.
struct HarvestObservation {
  double stamp_s = 0.0;
  std::vector<BollSighting> bolls;
  std::optional<Point3> end_effector;
  double rover_position_m = 0.0;  ///< along the row, when the frame was taken
};

/// The transitions of Algorithm 1 (Figure 13).
enum class HarvestAction { kForward, kBackward, kArmUp, kArmDown, kPick, kPassOn, kOutOfReach };
const char* toString(HarvestAction action);

/// "Equal" in Algorithm 1: tolerances, and the horizontal reach of the arm.
struct DecisionParams {
  double y_tolerance_m = 0.03;  ///< |Yb - Ym| within this: aligned along the row
  double z_tolerance_m = 0.03;  ///< |Zb - Zm| within this: at the boll's height
  double pick_reach_m = 0.37;   ///< |Xm - Xb| below this: the arm can pick (Algorithm 1, step 13)
  double y_forward_sign = 1.0;  ///< +1 when a larger camera y is further ahead along the row
  std::string check() const;    ///< empty when sound
};

/// The decision for one boll and the end effector, and how far to move.
struct HarvestDecision {
  HarvestAction action = HarvestAction::kPassOn;
  double rover_move_m = 0.0;   ///< kForward/kBackward: signed distance along the row
  double arm_depth_m = 0.0;    ///< kArmUp/kArmDown: target depth of the end effector (= Zb)
  double pick_offset_m = 0.0;  ///< kPick: horizontal move of the arm to the boll (Xb - Xm)
};

/// Algorithm 1, steps 8–14: compares the boll (b) with the end effector (m).
/// Yb > Ym → forward, Yb < Ym → backward; aligned in Y and Zm > Zb → arm up, Zm < Zb → arm down;
/// aligned in Y and Z and |Xm − Xb| < reach → pick; aligned but out of reach → kOutOfReach.
HarvestDecision decide(const Point3& boll, const Point3& end_effector, const DecisionParams& params);

}  // namespace control
}  // namespace cotton_harvester
