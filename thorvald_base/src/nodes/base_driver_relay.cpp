// base_driver's CAN relay: implement frames between the bus and can_frames_device_r/_t, bounded per cycle in both
// directions, with the allow-list (robot file's implement_can_ids or ~relay_allowed_ids) and per-sender refusals.
#include <algorithm>
#include <cmath>

#include "base_driver_ros.h"

namespace thorvald_base {

RelayIdList BaseDriverRos::readRelayIds(ParamReader& params, const RobotConfig& config) {
  RelayIdList list{config.implement_can_ids, config.source, "implement_can_ids"};
  if (!params.has("relay_allowed_ids")) return list;
  // The parameter overrides the robot file's list (e.g. on a test bench); the same ids are refused.
  const std::vector<double> ids =
      params.numbers("relay_allowed_ids", {}, ParamRange::closed(1, kMaxCanStdId), "", 0, kMaxModulesPerGroup);
  list = {{}, "base_driver", "~relay_allowed_ids"};
  for (size_t i = 0; i < ids.size(); ++i) {
    if (ids[i] != std::floor(ids[i])) {
      throw ConfigError("base_driver", "~relay_allowed_ids[" + std::to_string(i) + "]",
                        "must be an integer CAN id, found " + std::to_string(ids[i]));
    }
    list.ids.push_back(static_cast<int>(ids[i]));
  }
  return list;
}

void BaseDriverRos::relayFromBus() {
  // Bounded like the bus reads: a flood of implement frames cannot stretch the cycle with publishing.
  const auto frames = hardware_->takeRelayFrames();
  const size_t n = std::min(frames.size(), static_cast<size_t>(relay_max_received_per_cycle_));
  relay_received_dropped_ += frames.size() - n;
  for (size_t k = 0; k < n; ++k) {
    const auto& f = frames[k];
    CANFrame msg;
    msg.id = f.id;
    msg.length = f.length;
    for (size_t i = 0; i < 8; ++i) msg.data[i] = f.data[i];
    relay_pub_.publish(msg);
    ++relay_received_;
  }
}

void BaseDriverRos::refuseRelay(const std::string& sender, uint32_t id, const std::string& why) {
  ++relay_refused_;
  auto it = relay_refused_by_.find(sender);
  if (it == relay_refused_by_.end()) {
    // Bounded: past kMaxRelaySenders callers, the rest are counted together.
    it = relay_refused_by_.size() < kMaxRelaySenders ? relay_refused_by_.emplace(sender, 0).first
                                                     : relay_refused_by_.emplace("(other senders)", 0).first;
  }
  ++it->second;
  ROS_WARN_THROTTLE(1.0, "base_driver: relay refused frame 0x%03X from %s: %s (%lu refused from it so far)", id,
                    sender.c_str(), why.c_str(), it->second);
}

void BaseDriverRos::onRelayFrame(const ros::MessageEvent<const CANFrame>& event) {
  const CANFrame& msg = *event.getConstMessage();
  const std::string sender = event.getPublisherName();
  if (relay_muted_) {
    ++relay_dropped_;
    return;
  }
  if (relay_sent_this_cycle_ >= relay_max_per_cycle_) {
    ++relay_dropped_;
    ROS_WARN_THROTTLE(1.0, "base_driver: relay limited to %d frames per cycle; frames dropped", relay_max_per_cycle_);
    return;
  }
  if (!relay_allowed_.count(msg.id)) {
    refuseRelay(sender, msg.id, "id not in the allow-list (implement_can_ids or ~relay_allowed_ids)");
    return;
  }
  CanFrameData f;
  f.id = msg.id;
  f.length = msg.length;
  for (size_t i = 0; i < 8; ++i) f.data[i] = msg.data[i];
  std::string why;
  if (!hardware_->sendRelayFrame(f, &why)) {
    refuseRelay(sender, msg.id, why);
    return;
  }
  ++relay_sent_;
  ++relay_sent_this_cycle_;
}

bool BaseDriverRos::onMuteRelay(std_srvs::SetBool::Request& req, std_srvs::SetBool::Response& res) {
  relay_muted_ = req.data;
  res.success = true;
  res.message = relay_muted_ ? "relay muted" : "relay active";
  return true;
}

}  // namespace thorvald_base
