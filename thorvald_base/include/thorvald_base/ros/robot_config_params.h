#pragma once

#include <ros/node_handle.h>
#include <xmlrpcpp/XmlRpcValue.h>
#include <yaml-cpp/yaml.h>

#include <string>

#include "thorvald_base/robot_config.h"

namespace thorvald_base {

/// Most values (map entries, list items and scalars together) a robot file on the parameter server may expand to.
/// A real robot file has a few hundred; YAML aliases can make a few hundred bytes expand to billions.
constexpr size_t kMaxRobotFileValues = 20000;

/// Converts a parameter-server tree into the YAML tree the robot-file parser reads, so a robot file loaded with
/// `rosparam load` and one read from disk go through the same checks. Throws ConfigError (naming `source`) when the
/// tree holds more than `max_values` values, or when ROS shuts down (SIGINT) during the conversion.
YAML::Node toYaml(XmlRpc::XmlRpcValue& value, const std::string& source = "parameter tree",
                  size_t max_values = kMaxRobotFileValues);

/// Reads the robot file that `rosparam load` put into the namespace of `nh` (base_calculator, motor_drives,
/// batteries, pipes, corners, beams, casters, passive_wheels, io, implement_can_ids): only these keys, each bounded
/// in bytes, values and nesting before it is expanded (getParamBounded), never the whole namespace; SIGINT/SIGTERM
/// stops the reading. `file`, when known (a launch file passes it), names the file in messages. Throws ConfigError,
/// also when there is none, naming what was found instead: an empty namespace, an empty motor_drives, the key
/// nearest to motor_drives (`did you mean motor_drive?`), a list, a ROS 2 parameters file (and the sub-tree to
/// load). Misspelt group names (`caster:`) become warnings, as parseRobotConfig gives for a file.
RobotConfig robotConfigFromParams(const ros::NodeHandle& nh, const std::string& file = "");

}  // namespace thorvald_base
