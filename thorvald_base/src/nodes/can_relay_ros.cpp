#include "can_relay_ros.h"

#include <utility>

namespace thorvald_base {
namespace {

CANFrame toMessage(const CanFrameData& f) {
  CANFrame msg;
  msg.id = f.id;
  msg.length = f.length;
  for (size_t i = 0; i < 8; ++i) msg.data[i] = f.data[i];
  return msg;
}

CanFrameData fromMessage(const CANFrame& msg) {
  CanFrameData f;
  f.id = msg.id;
  f.length = msg.length;
  for (size_t i = 0; i < 8; ++i) f.data[i] = msg.data[i];
  return f;
}

}  // namespace

CanRelayRos::CanRelayRos(ros::NodeHandle nh, ros::NodeHandle pnh, BaseHardware& hardware, std::set<uint32_t> allowed,
                         CanRelayOptions options)
    : relay_(hardware, std::move(allowed), options) {
  pub_ = nh.advertise<CANFrame>("can_frames_device_r", 100);
  sub_ = nh.subscribe("can_frames_device_t", 100, &CanRelayRos::onFrame, this);
  mute_service_ = pnh.advertiseService("mute_relay", &CanRelayRos::onMute, this);
}

void CanRelayRos::cycle() {
  for (const auto& f : relay_.cycle()) pub_.publish(toMessage(f));
}

void CanRelayRos::onFrame(const ros::MessageEvent<const CANFrame>& event) {
  const CANFrame& msg = *event.getConstMessage();
  const RelayVerdict verdict = relay_.offer(event.getPublisherName(), fromMessage(msg));
  if (verdict.kind == RelayVerdict::Kind::kOverCycleBound) {
    ROS_WARN_THROTTLE(1.0, "base_driver: relay limited to %d frames per cycle; frames dropped",
                      relay_.options().max_sent_per_cycle);
  } else if (verdict.kind == RelayVerdict::Kind::kRefused) {
    ROS_WARN_THROTTLE(1.0, "base_driver: relay refused frame 0x%03X from %s: %s (%lu refused from it so far)", msg.id,
                      event.getPublisherName().c_str(), verdict.why.c_str(), verdict.refused_from_sender);
  }
}

bool CanRelayRos::onMute(std_srvs::SetBool::Request& req, std_srvs::SetBool::Response& res) {
  relay_.setMuted(req.data);
  res.success = true;
  res.message = relay_.muted() ? "relay muted" : "relay active";
  return true;
}

void CanRelayRos::diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) const {
  const CanRelayCounters& c = relay_.counters();
  stat.add("relay frames sent", c.sent);
  stat.add("relay frames received", c.received);
  stat.add("relay frames from the bus dropped (per-cycle bound)", c.received_dropped);
  stat.add("relay frames refused", c.refused);
  for (const auto& kv : c.refused_by) stat.add("relay frames refused from " + kv.first, kv.second);
  stat.add("relay frames dropped", c.dropped);
  stat.add("relay muted", relay_.muted());
}

}  // namespace thorvald_base
