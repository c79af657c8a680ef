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
    pnh.param("can_feedback_timeout", options().feedback_timeout_s, 0.06);
    if (!(options().feedback_timeout_s >= 0.005 && options().feedback_timeout_s <= 0.1)) {
      throw thorvald_base::ConfigError("base_driver", "~can_feedback_timeout",
                                       "must be in [0.005, 0.1] s (a silent drive must stop the base within 100 ms)");
    }
    int max_frames = 400;
    pnh.param("can_max_frames_per_cycle", max_frames, 400);
    if (max_frames < 16 || max_frames > 100000) {
      throw thorvald_base::ConfigError("base_driver", "~can_max_frames_per_cycle", "must be in [16, 100000]");
    }
    options().max_frames_per_poll = static_cast<size_t>(max_frames);
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
