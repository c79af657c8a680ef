#include "thorvald_can_devices/thorvald_drive.h"

#include <algorithm>
#include <cmath>

#include "thorvald_can_devices/canopen_protocol.h"
#include "thorvald_can_devices/drive_scaling.h"

namespace thorvald_can_devices {

ThorvaldController::ThorvaldController(CanBus* bus, std::vector<thorvald_base::DriveConfig> channels)
    : bus_(bus), channels_(std::move(channels)) {
  node_ = channels_.front().node;
  type_ = channels_.front().type;
  commands_.resize(channels_.size());
  updated_at_.assign(channels_.size(), -1.0);
  feedback_.resize(channels_.size());
}

std::string ThorvaldController::label() const {
  std::string names;
  for (const auto& c : channels_) names += (names.empty() ? "drive" : "+drive") + std::to_string(c.index);
  return names + " (thorvald node " + std::to_string(node_) + ")";
}

std::vector<uint32_t> ThorvaldController::receiveIds() const {
  std::vector<uint32_t> ids;
  for (uint32_t base : {thorvald_ids::kFeedback, thorvald_ids::kPower, thorvald_ids::kStatus, thorvald_ids::kInfo,
                        thorvald_ids::kHeartbeat})
    ids.push_back(base + static_cast<uint32_t>(node_));
  return ids;
}

std::vector<uint32_t> ThorvaldController::transmitIds() const {
  std::vector<uint32_t> ids;
  for (uint32_t base : {thorvald_ids::kCommand, thorvald_ids::kSetup, thorvald_ids::kMode, thorvald_ids::kSteering,
                        canopen_ids::kSdoRequest, canopen_ids::kSdoReply})
    ids.push_back(base + static_cast<uint32_t>(node_));
  return ids;
}

void ThorvaldController::start(double now_s) {
  now_s_ = now_s;
  last_start_sent_s_ = now_s;
  bus_->send(encodeNmt(NmtCommand::kStart, node_));
  bus_->send(encodeSetup(node_, {thorvald_setup::kCommandTimeoutMs, 500}));
  bus_->send(encodeMode(node_, ThorvaldMode::kDrive));
}

bool ThorvaldController::operational() const {
  return heard_ && nmt_state_ == kHeartbeatOperational && now_s_ - last_heartbeat_s_ <= kHeartbeatTimeoutS;
}

void ThorvaldController::handle(const CanFrame& f, double now_s) {
  now_s_ = now_s;
  const uint32_t base = f.stdId() - static_cast<uint32_t>(node_);
  bool ok = false;
  switch (base) {
    case thorvald_ids::kHeartbeat:
      if (auto hb = decodeHeartbeat(f)) {
        ok = true;
        heard_ = true;
        last_heartbeat_s_ = now_s;
        if (*hb == kHeartbeatOperational && nmt_state_ != kHeartbeatOperational) operational_since_s_ = now_s;
        nmt_state_ = *hb;
      }
      break;
    case thorvald_ids::kFeedback:
      if (auto fb = decodeFeedback(f)) {
        ok = true;
        onFeedback(*fb, now_s);
      }
      break;
    case thorvald_ids::kPower:
      ok = decodePower(f).has_value();
      break;
    case thorvald_ids::kStatus:
      if (auto st = decodeStatus(f)) {
        ok = true;
        status_frame_ = *st;
        status_seen_ = true;
      }
      break;
    case thorvald_ids::kInfo:
      if (auto info = decodeInfo(f)) {
        ok = true;
        onInfo(*info);
      }
      break;
    default:
      break;
  }
  if (!ok) ++malformed_;
}

void ThorvaldController::onFeedback(const ThorvaldFeedback& fb, double now_s) {
  const double dt = std::min(std::max(now_s - last_feedback_s_, 0.0), 0.1);
  last_feedback_s_ = now_s;
  const auto& c0 = channels_[0];
  auto& f0 = feedback_[0];
  f0.wheel_speed_radps = ThorvaldScaling::wheelSpeedFromRpm(fb.propulsion_rpm, c0);
  if (f0.valid) f0.wheel_position_rad += f0.wheel_speed_radps * dt;
  f0.valid = true;
  if (type_ == 0) {
    f0.steering_rad = ThorvaldScaling::steeringFromCount(fb.steering_count, c0);
    f0.steering_speed_radps = ThorvaldScaling::steeringSpeedFromRpm(fb.steering_rpm, c0);
  } else if (channels_.size() > 1) {
    auto& f1 = feedback_[1];
    f1.wheel_speed_radps = ThorvaldScaling::wheelSpeedFromRpm(fb.steering_rpm, channels_[1]);
    if (f1.valid) f1.wheel_position_rad += f1.wheel_speed_radps * dt;
    f1.valid = true;
  }
}

void ThorvaldController::onInfo(const ThorvaldInfo& info) {
  if (info.type == 1) {
    if (homing_ && info.home_direction == 0) {
      homing_ = false;
      bus_->send(encodeMode(node_, ThorvaldMode::kDrive));
    }
  } else if (info.type == 2) {
    if (info.controller_type != type_) {
      config_fault_ = "controller is type " + std::to_string(info.controller_type) + " but the robot file says type " +
                      std::to_string(type_);
    } else if (config_fault_.rfind("controller", 0) == 0) {
      config_fault_.clear();
    }
  } else if (info.type == 3 && type_ == 0) {
    if (std::fabs(info.encoder_ppr - channels_[0].str_enc_ppr) > 0.5) {
      config_fault_ = "steering encoder has " + std::to_string(info.encoder_ppr) + " ppr but str_enc_ppr is " +
                      std::to_string(static_cast<int>(channels_[0].str_enc_ppr));
    } else if (config_fault_.rfind("steering encoder", 0) == 0) {
      config_fault_.clear();
    }
  }
}

void ThorvaldController::tick(double now_s) {
  now_s_ = now_s;
  // A node that rebooted (boot-up) or sits in pre-operational is started again, twice a second at most.
  if (heard_ && nmt_state_ != kHeartbeatOperational && now_s - last_start_sent_s_ > 0.5) start(now_s);
}

void ThorvaldController::channelUpdated(size_t channel, double now_s) {
  updated_at_[channel] = now_s;
  for (double t : updated_at_)
    if (t != now_s) return;
  sendCommands();
}

void ThorvaldController::sendCommands() {
  if (!operational()) return;
  sequence_ = static_cast<int32_t>(static_cast<uint32_t>(sequence_) + 1U);
  const auto& c0 = channels_[0];
  bus_->send(encodeCommand(node_, {sequence_, ThorvaldScaling::propulsionCommand(commands_[0].wheel_speed_radps, c0)}));
  if (type_ == 0) {
    const int32_t max_rpm = clampToI32(ThorvaldScaling::steeringRpmFromSpeed(c0.str_sim_v, c0), 0, INT32_MAX);
    bus_->send(encodeSteering(node_, {max_rpm, ThorvaldScaling::steeringCommand(commands_[0].steering_rad, c0)}));
  } else if (channels_.size() > 1) {
    bus_->send(
        encodeSteering(node_, {0, ThorvaldScaling::propulsionCommand(commands_[1].wheel_speed_radps, channels_[1])}));
  }
}

thorvald_base::DriveStatus ThorvaldController::status(size_t) const {
  thorvald_base::DriveStatus s;
  s.homing = homing_;
  if (!heard_ || now_s_ - last_heartbeat_s_ > kHeartbeatTimeoutS) {
    s.online = false;
    s.text = heard_ ? "no heartbeat for more than 2 s" : "never answered";
    return s;
  }
  if (nmt_state_ != kHeartbeatOperational) {
    s.online = false;
    s.text = "not operational (NMT state 0x" + std::string(nmt_state_ == kHeartbeatBootUp ? "00" : "7F") + ")";
    return s;
  }
  // Heartbeats alone do not keep a drive: its feedback must keep coming (a heartbeat can be sent by anyone). A drive
  // that has just become operational gets kFirstFeedbackS for its first feedback (a drive, or a loaded host, may
  // take a few status periods to start); from then on feedback_timeout applies.
  const bool fed = last_feedback_s_ >= operational_since_s_;
  const double silent_s = now_s_ - std::max(last_feedback_s_, operational_since_s_);
  if (silent_s > (fed ? feedback_timeout_s_ : std::max(feedback_timeout_s_, kFirstFeedbackS))) {
    s.online = false;
    s.text = "no feedback for " + std::to_string(static_cast<int>(silent_s * 1000.0)) + " ms";
    return s;
  }
  std::string fault;
  if (bus_off_) fault = "bus off";
  if (!config_fault_.empty()) fault += (fault.empty() ? "" : ", ") + config_fault_;
  if (status_seen_) {
    const uint8_t relevant = static_cast<uint8_t>(
        status_frame_.flags &
        (type_ == 0 ? 0xFF : ~(thorvald_flags::kSteeringEncoderFault | thorvald_flags::kAlignmentFault)));
    const std::string flags = describeFlags(relevant);
    if (!flags.empty()) fault += (fault.empty() ? "" : ", ") + flags;
  }
  if (!fault.empty()) {
    s.fault = true;
    s.text = fault;
  } else {
    s.text = homing_ ? "homing" : "ok";
  }
  return s;
}

bool ThorvaldController::startHoming() {
  if (type_ != 0 || !operational()) return false;
  homing_ = true;
  bus_->send(encodeMode(node_, ThorvaldMode::kHomeSteering));
  return true;
}

void ThorvaldController::clearFault() { bus_->send(encodeSetup(node_, {thorvald_setup::kFaultReset, 1})); }

void ThorvaldDrive::update(double now_s) { controller_->channelUpdated(channel_, now_s); }

}  // namespace thorvald_can_devices
