#pragma once

namespace thorvald_base {

/// The steering angle chosen for a wanted wheel direction.
struct SteeringChoice {
  double angle_rad = 0.0;     ///< commanded steering angle, always within +-limit
  double speed_sign = 1.0;    ///< -1 when the wheel is turned 180 deg from the wanted direction and runs backwards
  double speed_factor = 1.0;  ///< cos of the angle still missing when the limit prevents the wanted direction
};

/// Chooses between a wanted wheel direction and its 180-degree twin (with reversed speed): the one inside
/// +-limit_rad; if both are, the one the steering reaches sooner from `current_rad` (steering cannot wrap through
/// +-pi because of the cable, so travel is the plain difference). If neither is inside (limits below 90 deg),
/// the limit closest to the wanted direction, with the speed reduced to the component along it.
SteeringChoice chooseSteering(double wanted_rad, double current_rad, double limit_rad);

/// Common propulsion scale while steered wheels still turn towards their targets: 1 when every wheel is within
/// `aligned_rad` of its target, 0 at `stopped_rad` or more, linear in between, so the wheels do not fight.
double alignmentScale(double max_steering_error_rad, double aligned_rad, double stopped_rad);

}  // namespace thorvald_base
