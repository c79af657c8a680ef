#include "thorvald_can_devices/cia402_drive.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "thorvald_can_devices/drive_scaling.h"

namespace thorvald_can_devices {
namespace {
constexpr double kSdoTimeoutS = 0.2;
constexpr int kSdoAttempts = 3;
SdoMessage write(uint16_t index, uint8_t sub, uint32_t value, uint8_t size) {
  SdoMessage m;
  m.kind = SdoMessage::Kind::kWriteRequest;
  m.index = index;
  m.subindex = sub;
  m.value = value;
  m.size = size;
  return m;
}
std::string hex(uint32_t v, int digits) {
  char buf[16];
  std::snprintf(buf, sizeof(buf), "0x%0*X", digits, v);
  return buf;
}
}  // namespace

Cia402Axis::Cia402Axis(CanBus* bus, Setup setup) : bus_(bus), setup_(std::move(setup)) {
  const bool position = setup_.kind == Kind::kPosition;
  sdo_writes_ = {
      write(cia402::kProducerHeartbeat, 0, 100, 2),
      write(cia402::kConsumerHeartbeat, 1, (static_cast<uint32_t>(kHostNode) << 16) | kHostHeartbeatTimeoutMs, 4),
      write(cia402::kModes, 0,
            static_cast<uint8_t>(position ? cia402::kModeProfilePosition : cia402::kModeProfileVelocity), 1),
      write(cia402::kProfileAcceleration, 0, setup_.profile_acceleration, 4),
      write(cia402::kProfileDeceleration, 0, setup_.profile_acceleration, 4),
  };
  if (position) sdo_writes_.push_back(write(cia402::kProfileVelocity, 0, setup_.profile_velocity, 4));
}

std::vector<uint32_t> Cia402Axis::receiveIds() const {
  const uint32_t n = static_cast<uint32_t>(setup_.node);
  return {canopen_ids::kTpdo1 + n, canopen_ids::kTpdo2 + n, canopen_ids::kSdoReply + n, canopen_ids::kEmcy + n,
          canopen_ids::kHeartbeat + n};
}
std::vector<uint32_t> Cia402Axis::transmitIds() const {
  const uint32_t n = static_cast<uint32_t>(setup_.node);
  return {canopen_ids::kRpdo1 + n, 0x300 + n, 0x400 + n, 0x500 + n, canopen_ids::kSdoRequest + n};
}

void Cia402Axis::start(double now_s) {
  now_s_ = now_s;
  phase_ = Phase::kConfiguring;
  failure_.clear();
  sdo_next_ = 0;
  sdo_attempts_ = 0;
  sendNextSdo(now_s);
}

void Cia402Axis::sendNextSdo(double now_s) {
  if (sdo_next_ >= sdo_writes_.size()) {
    phase_ = Phase::kStarting;
    bus_->send(encodeNmt(NmtCommand::kStart, setup_.node));
    return;
  }
  ++sdo_attempts_;
  sdo_sent_s_ = now_s;
  bus_->send(encodeSdoRequest(setup_.node, sdo_writes_[sdo_next_]));
}

bool Cia402Axis::online() const { return heard_ && now_s_ - last_heartbeat_s_ <= kHeartbeatTimeoutS; }

bool Cia402Axis::feedbackSilent() const {
  return feedback_seen_ && syncs_unanswered_ > 3 && now_s_ - last_tpdo_s_ > feedback_timeout_s_;
}

bool Cia402Axis::operational() const {
  return online() && nmt_state_ == 0x05 && state_ == Cia402State::kOperationEnabled;
}

void Cia402Axis::handle(const CanFrame& f, double now_s) {
  now_s_ = now_s;
  const uint32_t base = f.stdId() - static_cast<uint32_t>(setup_.node);
  bool ok = false;
  if (base == canopen_ids::kHeartbeat) {
    if (f.length == 1 && (f.data[0] == 0x00 || f.data[0] == 0x04 || f.data[0] == 0x05 || f.data[0] == 0x7F)) {
      ok = true;
      heard_ = true;
      last_heartbeat_s_ = now_s;
      if (f.data[0] == 0x00 && phase_ != Phase::kConfiguring) start(now_s);  // rebooted: configure again
      nmt_state_ = f.data[0];
    }
  } else if (base == canopen_ids::kTpdo1) {
    if (auto p = decodeTpdo1(f)) {
      ok = true;
      statusword_ = p->statusword;
      state_ = stateOf(statusword_);
      actual_velocity_ = p->actual_velocity;
      feedback_seen_ = true;
      last_tpdo_s_ = now_s;
      syncs_unanswered_ = 0;
      if (setpoint_pending_ && (statusword_ & cia402::kSwSetPointAck)) setpoint_pending_ = false;
    }
  } else if (base == canopen_ids::kTpdo2) {
    if (auto p = decodeTpdo2(f)) {
      ok = true;
      actual_position_ = p->actual_position;
    }
  } else if (base == canopen_ids::kEmcy) {
    if (auto e = decodeEmergency(f)) {
      ok = true;
      emcy_code_ = e->error_code;
    }
  } else if (base == canopen_ids::kSdoReply) {
    if (auto m = decodeSdo(f)) {
      ok = true;
      if (phase_ == Phase::kConfiguring && sdo_next_ < sdo_writes_.size() && m->index == sdo_writes_[sdo_next_].index &&
          m->subindex == sdo_writes_[sdo_next_].subindex) {
        if (m->kind == SdoMessage::Kind::kWriteAck) {
          ++sdo_next_;
          sdo_attempts_ = 0;
          sendNextSdo(now_s);
        } else if (m->kind == SdoMessage::Kind::kAbort) {
          phase_ = Phase::kFailed;
          failure_ = "SDO write " + hex(m->index, 4) + " aborted with code " + hex(m->value, 8);
        }
      }
    }
  }
  if (!ok) ++malformed_;
}

void Cia402Axis::tick(double now_s) {
  now_s_ = now_s;
  if (phase_ == Phase::kConfiguring && now_s - sdo_sent_s_ > kSdoTimeoutS) {
    if (sdo_attempts_ >= kSdoAttempts) {
      phase_ = Phase::kFailed;
      failure_ = "SDO write " + hex(sdo_writes_[sdo_next_].index, 4) + " not answered";
      sdo_sent_s_ = now_s;
    } else {
      sendNextSdo(now_s);
    }
  } else if (phase_ == Phase::kFailed && now_s - sdo_sent_s_ > 2.0) {
    start(now_s);  // try the configuration again every 2 s
  } else if (phase_ == Phase::kStarting && heard_ && nmt_state_ == 0x05) {
    phase_ = Phase::kRunning;
  } else if (phase_ == Phase::kStarting && now_s - sdo_sent_s_ > 0.5) {
    sdo_sent_s_ = now_s;
    bus_->send(encodeNmt(NmtCommand::kStart, setup_.node));
  }
  // Before the first command cycle, walk the state machine so that start-up reaches operation enabled.
  if (phase_ == Phase::kRunning && state_ != Cia402State::kOperationEnabled) sendTarget();
}

void Cia402Axis::sendTarget() {
  if (phase_ != Phase::kRunning || !online()) return;
  uint16_t cw = controlwordTowardsOperation(state_);
  if (state_ == Cia402State::kFault || state_ == Cia402State::kFaultReactionActive) {
    cw = 0;
    if (fault_reset_pending_) {
      cw = fault_reset_step_ == 0 ? 0x00 : cia402::kCwFaultReset;  // rising edge of bit 7
      if (++fault_reset_step_ > 1) {
        fault_reset_pending_ = false;
        fault_reset_step_ = 0;
      }
    }
  } else {
    fault_reset_pending_ = false;
    fault_reset_step_ = 0;
  }
  int32_t target = target_;
  if (setup_.kind == Kind::kPosition && state_ == Cia402State::kOperationEnabled) {
    if (target_ != sent_target_ && !setpoint_pending_) {
      sent_target_ = target_;
      setpoint_pending_ = true;
    }
    target = sent_target_;
    cw |= cia402::kCwChangeImmediately;
    if (setpoint_pending_) cw |= cia402::kCwNewSetPoint;
  } else if (state_ != Cia402State::kOperationEnabled) {
    target = setup_.kind == Kind::kVelocity ? 0 : actual_position_;
    sent_target_ = target;
  }
  bus_->send(encodeRpdo1(setup_.node, {cw, target}));
}

std::string Cia402Axis::fault() const {
  std::string f;
  if (bus_off_) f = "bus off";
  if (phase_ == Phase::kFailed) f += (f.empty() ? "" : ", ") + failure_;
  if (state_ == Cia402State::kFault || state_ == Cia402State::kFaultReactionActive) {
    f +=
        (f.empty() ? "" : ", ") + std::string("drive fault") + (emcy_code_ ? " (EMCY " + hex(emcy_code_, 4) + ")" : "");
  }
  return f;
}

std::string Cia402Axis::describe() const {
  if (!heard_) return setup_.name + ": never answered";
  if (!online()) return setup_.name + ": no heartbeat for more than 2 s";
  const std::string f = fault();
  if (!f.empty()) return setup_.name + ": " + f;
  if (!operational()) return setup_.name + ": starting (" + toString(state_) + ")";
  return setup_.name + ": operation enabled";
}

Cia402Drive::Cia402Drive(const thorvald_base::DriveConfig& config, std::shared_ptr<Cia402Axis> propulsion,
                         std::shared_ptr<Cia402Axis> steering)
    : config_(config), propulsion_(std::move(propulsion)), steering_(std::move(steering)) {}

std::vector<Cia402Axis::Setup> Cia402Drive::axesFor(const thorvald_base::DriveConfig& d) {
  std::vector<Cia402Axis::Setup> out;
  Cia402Axis::Setup p;
  p.name = "drive" + std::to_string(d.index) + " propulsion";
  p.node = d.node;
  p.kind = Cia402Axis::Kind::kVelocity;
  p.profile_acceleration =
      static_cast<uint32_t>(std::lround(d.prp_sim_a / d.r_wheel * Cia402Scaling::propulsionIncrementsPerRad(d)));
  out.push_back(p);
  if (d.steered()) {
    Cia402Axis::Setup s;
    s.name = "drive" + std::to_string(d.index) + " steering";
    s.node = d.node + kCia402SteeringNodeOffset;
    s.kind = Cia402Axis::Kind::kPosition;
    s.profile_velocity = static_cast<uint32_t>(std::lround(d.str_sim_v * Cia402Scaling::steeringIncrementsPerRad(d)));
    s.profile_acceleration = s.profile_velocity * 10;
    out.push_back(s);
  }
  return out;
}

void Cia402Drive::update(double now_s) {
  propulsion_->setTarget(Cia402Scaling::velocityFromWheelSpeed(command_.wheel_speed_radps, config_));
  propulsion_->sendTarget();
  if (steering_) {
    steering_->setTarget(Cia402Scaling::positionFromSteering(command_.steering_rad, config_));
    steering_->sendTarget();
  }
  const double speed = Cia402Scaling::wheelSpeedFromVelocity(propulsion_->actualVelocity(), config_);
  if (last_update_s_ >= 0.0 && now_s > last_update_s_)
    wheel_position_rad_ += speed * std::min(now_s - last_update_s_, 0.1);
  last_update_s_ = now_s;
}

thorvald_base::DriveFeedback Cia402Drive::feedback() const {
  thorvald_base::DriveFeedback f;
  f.valid = propulsion_->hasFeedback() && (!steering_ || steering_->hasFeedback());
  f.wheel_speed_radps = Cia402Scaling::wheelSpeedFromVelocity(propulsion_->actualVelocity(), config_);
  f.wheel_position_rad = wheel_position_rad_;
  if (steering_) {
    f.steering_rad = Cia402Scaling::steeringFromPosition(steering_->actualPosition(), config_);
    f.steering_speed_radps = Cia402Scaling::steeringSpeedFromVelocity(steering_->actualVelocity(), config_);
  }
  return f;
}

thorvald_base::DriveStatus Cia402Drive::status() const {
  thorvald_base::DriveStatus s;
  std::vector<const Cia402Axis*> axes{propulsion_.get()};
  if (steering_) axes.push_back(steering_.get());
  std::string text;
  for (const Cia402Axis* a : axes) {
    if (!a->online()) s.online = false;
    if (!a->fault().empty()) s.fault = true;
    text += (text.empty() ? "" : "; ") + a->describe();
  }
  // Not yet (or no longer) in operation enabled without a fault: not usable, as if lost.
  if (s.online && !s.fault) {
    for (const Cia402Axis* a : axes)
      if (!a->operational()) s.online = false;
  }
  // A silent axis is named alone: "operation enabled" beside it would hide why the drive is lost.
  std::string silent;
  for (const Cia402Axis* a : axes) {
    if (a->operational() && a->feedbackSilent()) {
      s.online = false;
      silent += (silent.empty() ? "" : "; ") + a->label() + ": no PDO answer to SYNC";
    }
  }
  s.text = silent.empty() ? text : silent;
  return s;
}

void Cia402Drive::clearFault() {
  propulsion_->clearFault();
  if (steering_) steering_->clearFault();
}

}  // namespace thorvald_can_devices
