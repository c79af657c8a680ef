// The pluginlib face of CanBaseHardware: reads the options the robot file does not hold from base_driver's
// private parameters (through base_driver's ParamReader) and logs the start-up report.
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>

#include "thorvald_common/ros/param_reader.h"
#include "thorvald_can_devices/can_base_hardware.h"

namespace thorvald_can_devices {

class CanBaseHardwarePlugin : public CanBaseHardware {
 public:
  void readParameters(thorvald_common::ParamReader& params) override {
    options().log_path = params.text("can_log", "");
    options().startup_timeout_s =
        params.number("can_startup_timeout", 3.0, thorvald_common::ParamRange::closed(0.0, 60.0), "s");
    // A silent drive must stop the base within 100 ms.
    options().feedback_timeout_s =
        params.number("can_feedback_timeout", 0.06, thorvald_common::ParamRange::closed(0.005, 0.1), "s");
    options().max_frames_per_poll = static_cast<size_t>(params.integer("can_max_frames_per_cycle", 400, 16, 100000));
  }

  void initialize(const thorvald_base::RobotConfig& config, const std::string& interface_type,
                  const std::string& interface_name) override {
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
