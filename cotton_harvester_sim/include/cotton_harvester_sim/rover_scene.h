#pragma once

#include <string>

#include "cotton_harvester_sim/rover_sim.h"

namespace cotton_harvester {
namespace sim {

/// The wheels' joints and actuators in the scene (front ones on the front body, the encoder's).
inline constexpr const char* kRoverWheelNames[4] = {"wheel_front_left", "wheel_front_right", "wheel_rear_left",
                                                    "wheel_rear_right"};

/// The MJCF of the rover standing on its row: `worldbody` (the row's geoms, from thorvald_sim::makeCottonRowWorld)
/// followed by the rover's rear and front bodies on the articulation joint, its four wheels, the camera beam, the
/// arm's mast, the two-axis arm with the orange end-effector housing, and their actuators. `params` must pass
/// RoverSimParams::check().
std::string roverSceneXml(const RoverSimParams& params, const std::string& worldbody);

}  // namespace sim
}  // namespace cotton_harvester
