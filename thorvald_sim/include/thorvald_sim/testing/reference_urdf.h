#pragma once

#include <string>

#include <thorvald_base/robot_config.h>

namespace thorvald_sim {

/// A small URDF of the shape thorvald_model's urdf_generator writes (root `base_link` on the ground under the
/// robot's centre; per drive a `steering<i>` joint about z (type 0) and a `wheel<i>` joint about the axle to
/// `wheel_link<i>`; casters and passive wheels; masses everywhere; names prefixed `<tf_prefix>/`). Used by the
/// tests, the benchmarks and the demo so they do not depend on thorvald_model; the node itself reads
/// `robot_description`. `body_mass_kg` is the frame's mass without drives.
std::string referenceUrdf(const thorvald_base::RobotConfig& robot, const std::string& tf_prefix,
                          double body_mass_kg = 120.0);

}  // namespace thorvald_sim
