#pragma once

#include <diagnostic_updater/DiagnosticStatusWrapper.h>
#include <ros/ros.h>
#include <std_srvs/SetBool.h>

#include <set>

#include "thorvald_base/CANFrame.h"
#include "thorvald_base/can_relay.h"

namespace thorvald_base {

/// base_driver's relay on ROS: moves frames between can_frames_device_t / can_frames_device_r and a CanRelay (which
/// decides), serves ~mute_relay, logs refusals (throttled) and reports the relay's counters in diagnostics.
class CanRelayRos {
 public:
  /// `hardware` must outlive this object.
  CanRelayRos(ros::NodeHandle nh, ros::NodeHandle pnh, BaseHardware& hardware, std::set<uint32_t> allowed,
              CanRelayOptions options);

  /// Once per control cycle: publishes the cycle's frames from the bus.
  void cycle();
  /// Adds the relay's counters to base_driver's "base" diagnostics.
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) const;

 private:
  void onFrame(const ros::MessageEvent<const CANFrame>& event);
  bool onMute(std_srvs::SetBool::Request& req, std_srvs::SetBool::Response& res);

  CanRelay relay_;
  ros::Publisher pub_;
  ros::Subscriber sub_;
  ros::ServiceServer mute_service_;
};

}  // namespace thorvald_base
