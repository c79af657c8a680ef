// can_device_sim: every drive controller and battery enclosure of the robot file, answering on a CAN bus as the
// hardware does. Started in the robot's namespace next to base_driver (same ~can_interface_type/_name).
#include <ros/ros.h>
#include <std_msgs/String.h>

#include <chrono>
#include <csignal>
#include <memory>
#include <sstream>

#include "thorvald_common/ros/param_reader.h"
#include "thorvald_base/ros/robot_config_params.h"
#include "thorvald_can_devices/InjectFault.h"
#include "thorvald_can_devices/candump_log.h"
#include "thorvald_can_devices/device_sim.h"

namespace thorvald_can_devices {
namespace {

double steadyS() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

class CanDeviceSimNode {
 public:
  CanDeviceSimNode(ros::NodeHandle nh, ros::NodeHandle pnh) : nh_(nh) {
    thorvald_common::ParamReader params(pnh, "can_device_sim");
    const thorvald_base::RobotConfig config = thorvald_base::robotConfigFromParams(nh, params.text("robot_file", ""));
    for (const auto& w : config.warnings) ROS_WARN_STREAM(w);
    const std::string type = params.choice("can_interface_type", "socketcan", {"socketcan", "virtual"});
    const std::string name = params.text("can_interface_name", "can0");
    const std::string log = params.text("can_log", "");
    rate_hz_ = params.number("rate", 500.0, thorvald_common::ParamRange::closed(10.0, 5000.0), "Hz");
    params.finish();
    bus_ = openCanBus(type, name);
    if (!log.empty())
      bus_ = std::make_unique<LoggingCanBus>(std::move(bus_), log, type == "virtual" ? "vcan_" + name : name);
    sim_ = std::make_unique<DeviceSim>(config);
    service_ = pnh.advertiseService("inject_fault", &CanDeviceSimNode::onInject, this);
    fault_sub_ = pnh.subscribe("fault", 10, &CanDeviceSimNode::onFaultTopic, this);
    ROS_INFO_STREAM("can_device_sim: " << sim_->thorvaldDrives().size() << " Thorvald controller(s), "
                                       << sim_->cia402Axes().size() << " CiA 402 axis/axes on " << bus_->description()
                                       << " at " << rate_hz_ << " Hz");
  }

  void run() {
    const double period = 1.0 / rate_hz_;
    double next = steadyS();
    while (ros::ok()) {
      const double wait = next - steadyS();
      if (wait > 0.0) bus_->waitReadable(wait);  // wakes on the first frame: answers (SDO, SYNC) come at once
      const double now = steadyS();
      sim_->spinOnce(now, *bus_);
      if (now >= next) next = std::max(next + period, now - period);
      ros::spinOnce();
    }
  }

 private:
  bool onInject(InjectFault::Request& req, InjectFault::Response& res) {
    res.success = sim_->inject(req.target, req.fault, req.active, *bus_, &res.message);
    if (res.success) {
      ROS_WARN_STREAM("can_device_sim: " << res.message);
    } else {
      ROS_ERROR_STREAM("can_device_sim: inject_fault refused: " << res.message);
    }
    return true;
  }
  /// "<target> <fault> on|off", e.g. "drive1 silent on".
  void onFaultTopic(const std_msgs::String& msg) {
    std::istringstream in(msg.data);
    InjectFault::Request req;
    InjectFault::Response res;
    std::string state;
    in >> req.target >> req.fault >> state;
    if (state != "on" && state != "off") {
      ROS_ERROR_STREAM("can_device_sim: ~fault wants '<target> <fault> on|off', got '" << msg.data << "'");
      return;
    }
    req.active = state == "on";
    onInject(req, res);
  }

  ros::NodeHandle nh_;
  double rate_hz_ = 500.0;
  std::unique_ptr<CanBus> bus_;
  std::unique_ptr<DeviceSim> sim_;
  ros::ServiceServer service_;
  ros::Subscriber fault_sub_;
};

}  // namespace
}  // namespace thorvald_can_devices

namespace {
// SIGTERM (as SIGINT) ends the loop, so the bus endpoint is closed and its socket file removed.
void onTerminate(int) { ros::requestShutdown(); }
}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "can_device_sim");
  std::signal(SIGTERM, onTerminate);
  ros::NodeHandle nh, pnh("~");
  std::unique_ptr<thorvald_can_devices::CanDeviceSimNode> node;
  try {
    node = std::make_unique<thorvald_can_devices::CanDeviceSimNode>(nh, pnh);
  } catch (const std::exception& e) {
    ROS_FATAL_STREAM("can_device_sim cannot start: " << e.what());
    return 1;
  }
  node->run();
  return 0;
}
