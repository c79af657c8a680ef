#pragma once

#include <ros/node_handle.h>
#include <xmlrpcpp/XmlRpcValue.h>
#include <yaml-cpp/yaml.h>

#include "thorvald_base/robot_config.h"

namespace thorvald_base {

/// Converts a parameter-server tree into the YAML tree the robot-file parser reads, so a robot file loaded with
/// `rosparam load` and one read from disk go through the same checks.
YAML::Node toYaml(XmlRpc::XmlRpcValue& value);

/// Reads the robot file that `rosparam load` put into the namespace of `nh` (base_calculator, motor_drives,
/// batteries, pipes, corners, beams, casters, passive_wheels, io). Throws ConfigError, also when there is none.
RobotConfig robotConfigFromParams(const ros::NodeHandle& nh);

}  // namespace thorvald_base
