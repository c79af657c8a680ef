#pragma once

#include <ros/node_handle.h>

#include "thorvald_base/robot_config.h"

namespace thorvald_can_devices {

/// Reads the robot file that `rosparam load` put into the namespace of `nh` (as base_driver does).
/// Throws thorvald_base::ConfigError naming what is missing or wrong.
thorvald_base::RobotConfig robotConfigFromParams(const ros::NodeHandle& nh);

}  // namespace thorvald_can_devices
