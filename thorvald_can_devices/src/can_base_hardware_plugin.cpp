// The pluginlib face of CanBaseHardware: reads the options the robot file does not hold from base_driver's
// private parameters and logs the start-up report.
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>

#include "thorvald_can_devices/can_base_hardware.h"

namespace thorvald_can_devices {

class CanBaseHardwarePlugin : public CanBaseHardware {
 public:
  void initialize(const thorvald_base::RobotConfig& config, const std::string& interface_type,
                  const std::string& interface_name) override {
    ros::NodeHandle pnh("~");
    pnh.param<std::string>("can_log", options().log_path, "");
    pnh.param("can_startup_timeout", options().startup_timeout_s, 3.0);
    if (!(options().startup_timeout_s >= 0.0 && options().startup_timeout_s <= 60.0)) {
      throw thorvald_base::ConfigError("base_driver", "~can_startup_timeout", "must be in [0, 60] s");
    }
    CanBaseHardware::initialize(config, interface_type, interface_name);
    ROS_INFO_STREAM("CAN base on " << bus().description()
                                   << (options().log_path.empty() ? "" : ", logging to " + options().log_path));
    for (const auto& device : notAnswering()) {
      ROS_ERROR_STREAM("CAN base: " << device << " did not reach operation at start-up");
    }
  }
};

}  // namespace thorvald_can_devices

PLUGINLIB_EXPORT_CLASS(thorvald_can_devices::CanBaseHardwarePlugin, thorvald_base::BaseHardware)
