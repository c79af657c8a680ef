#pragma once

#include <string>
#include <vector>

#include "thorvald_base/robot_config.h"
#include "thorvald_model/urdf_tree.h"

namespace thorvald_model {

/// How the generated model is named.
struct ModelOptions {
  std::string robot_name = "thorvald";  ///< <robot name="...">
  std::string tf_prefix;                ///< empty: no prefix; else every link and joint is "<tf_prefix>/<name>"
  bool floating_base =
      false;  ///< add a link `world` (never prefixed) and a floating joint to base_link (MuJoCo free body)
};

/// Prefixes a link or joint name the way base_driver does: "<tf_prefix>/<name>", or the name alone.
std::string prefixed(const std::string& tf_prefix, const std::string& name);

/// Turns a parsed robot file into links and joints (see README: "The model"). Modules are drawn as boxes and
/// cylinders sized like the real Thorvald modules; masses come from their volumes and per-module densities.
/// Throws thorvald_base::ConfigError naming the module and key for a robot file that cannot be modelled.
UrdfTree buildModel(const thorvald_base::RobotConfig& config, const ModelOptions& options);

/// The joints base_driver publishes on joint_states for this robot: `steering<i>` of every type-0 drive, then
/// `wheel<i>` of every drive, prefixed like buildModel's names.
std::vector<std::string> baseDriverJointNames(const thorvald_base::RobotConfig& config, const std::string& tf_prefix);

/// The passive joints (caster swivels and wheels, passive wheels) that nothing in base_driver publishes, so
/// that robot_state_publisher can be given them by the passive_joint_states node.
std::vector<std::string> passiveJointNames(const thorvald_base::RobotConfig& config, const std::string& tf_prefix);

/// The joints of a URDF document that take one position (revolute, continuous, prismatic), in document order.
/// Throws std::runtime_error when the text is not a URDF robot.
std::vector<std::string> movableJointNames(const std::string& urdf_xml);

/// What the passive_joint_states node publishes: passiveJointNames, then every movable joint of `urdf_xml` (the
/// namespace's robot_description; empty: none) that neither base_driver (baseDriverJointNames) nor that list
/// publishes, each once, in document order. Throws std::runtime_error when `urdf_xml` is given and not a URDF robot.
std::vector<std::string> unpublishedJointNames(const thorvald_base::RobotConfig& config, const std::string& tf_prefix,
                                               const std::string& urdf_xml);

}  // namespace thorvald_model
