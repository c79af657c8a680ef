#pragma once

#include <XmlRpcValue.h>

#include <vector>

#include "thorvald_common/ros/param_reader.h"
#include "thorvald_sim/actors.h"
#include "thorvald_sim/greenhouse_world.h"

namespace thorvald_sim {

/// Reads ~greenhouse/* and the variation: ~world_variation (profile none | harsh), then each
/// ~greenhouse/variation/<key> over the profile. Throws ParamError naming the key.
void readGreenhouseParams(thorvald_common::ParamReader& params, GreenhouseParams* g);

/// Parses ~actors: a list of {name, kind: person | trolley, path: [[x, y, t], ...], loop, random_walk: {region:
/// [x_min, x_max, y_min, y_max], speed, pause, seed}, rail_set, radius, height, length}. With `rail_set: k` the
/// path's and region's x, y are in rail set k's frame (origin between its pipes at their start, x along the rails),
/// looked up in `truth` (null: not a greenhouse, rail_set refused). Throws std::invalid_argument naming the entry
/// and key.
std::vector<ActorSpec> parseActors(XmlRpc::XmlRpcValue& list, const GreenhouseTruth* truth);

}  // namespace thorvald_sim
