#include "thorvald_can_devices/cia402_axis_sim.h"

#include <algorithm>
#include <cmath>

#include "sim_motion.h"
#include "thorvald_can_devices/cia402_drive.h"

namespace thorvald_can_devices {

Cia402AxisSim::Cia402AxisSim(const thorvald_base::DriveConfig& drive, bool steering)
    : drive_(drive), steering_(steering), node_(drive.node + (steering ? kCia402SteeringNodeOffset : 0)) {}

void Cia402AxisSim::reboot() {
  nmt_ = kHeartbeatBootUp;
  boot_sent_ = false;
  state_ = Cia402State::kSwitchOnDisabled;
  heartbeat_ms_ = consumer_ = 0;
  mode_ = 0;
  velocity_ = 0.0;
  target_velocity_ = 0;
  controlword_ = 0;
  last_host_heartbeat_s_ = -1.0;
}

void Cia402AxisSim::setFault(const std::string& fault, bool active) {
  if (fault == "silent") {
    if (faults_.silent && !active) reboot();
    faults_.silent = active;
  } else if (fault == "stall") {
    faults_.stall = active;
  } else if (fault == "encoder") {
    faults_.encoder = active;
  }
}

void Cia402AxisSim::enterFault(uint16_t emcy, CanBus& bus) {
  if (state_ == Cia402State::kFault) return;
  state_ = Cia402State::kFault;
  velocity_ = 0.0;
  bus.send(encodeEmergency(node_, {emcy, 0x01}));
}

void Cia402AxisSim::handle(const CanFrame& f, CanBus& bus, double now_s) {
  if (faults_.silent || f.isError() || f.isExtended() || f.isRemote()) return;
  const uint32_t id = f.stdId();
  const uint32_t n = static_cast<uint32_t>(node_);
  if (id == canopen_ids::kNmt) {
    const auto m = decodeNmt(f);
    if (!forNode(m, node_)) return;
    if (const auto state = nmtStateAfter(m->command)) {
      nmt_ = *state;
    } else {
      reboot();
    }
  } else if (id == canopen_ids::kHeartbeat + kHostNode && f.length == 1) {
    last_host_heartbeat_s_ = now_s;
  } else if (id == canopen_ids::kSync && f.length == 0) {
    if (nmt_ != kHeartbeatOperational) return;
    sendTpdos(bus);
  } else if (id == canopen_ids::kSdoRequest + n) {
    if (nmt_ == kHeartbeatStopped || nmt_ == kHeartbeatBootUp) return;
    answerSdo(f, bus);
  } else if (id == canopen_ids::kRpdo1 + n) {
    if (nmt_ != kHeartbeatOperational) return;
    if (const auto p = decodeRpdo1(f)) applyRpdo1(*p);
  }
}

void Cia402AxisSim::sendTpdos(CanBus& bus) const {
  uint16_t sw = statuswordOf(state_) | 0x0200;
  if (setpoint_ack_) sw |= cia402::kSwSetPointAck;
  const bool reached =
      steering_ ? std::fabs(position_ - target_position_) < 1.0 : std::fabs(velocity_ - target_velocity_) < 1.0;
  if (reached) sw |= cia402::kSwTargetReached;
  bus.send(encodeTpdo1(node_, {sw, clampToI32(faults_.encoder ? 0.0 : velocity_, INT32_MIN, INT32_MAX)}));
  bus.send(encodeTpdo2(node_, {clampToI32(position_, INT32_MIN, INT32_MAX), mode_}));
}

void Cia402AxisSim::answerSdo(const CanFrame& f, CanBus& bus) {
  const auto m = decodeSdo(f);
  SdoMessage reply;
  if (!m) {
    reply.kind = SdoMessage::Kind::kAbort;
    reply.value = 0x05040001;  // command specifier not valid
    bus.send(encodeSdoReply(node_, reply));
    return;
  }
  reply.index = m->index;
  reply.subindex = m->subindex;
  if (m->kind == SdoMessage::Kind::kWriteRequest) {
    writeObject(*m, reply);
  } else if (m->kind == SdoMessage::Kind::kReadRequest) {
    readObject(*m, reply);
  } else {
    return;
  }
  bus.send(encodeSdoReply(node_, reply));
}

void Cia402AxisSim::writeObject(const SdoMessage& m, SdoMessage& reply) {
  reply.kind = SdoMessage::Kind::kWriteAck;
  switch (m.index) {
    case cia402::kProducerHeartbeat:
      heartbeat_ms_ = m.value;
      break;
    case cia402::kConsumerHeartbeat:
      consumer_ = m.value;
      break;
    case cia402::kModes:
      mode_ = static_cast<int8_t>(m.value);
      break;
    case cia402::kProfileVelocity:
      profile_velocity_ = m.value;
      break;
    case cia402::kProfileAcceleration:
      profile_acceleration_ = m.value;
      break;
    case cia402::kProfileDeceleration:
      profile_deceleration_ = m.value;
      break;
    default:
      reply.kind = SdoMessage::Kind::kAbort;
      reply.value = 0x06020000;  // object does not exist
  }
}

void Cia402AxisSim::readObject(const SdoMessage& m, SdoMessage& reply) const {
  reply.kind = SdoMessage::Kind::kReadReply;
  reply.size = 4;
  switch (m.index) {
    case cia402::kStatusword:
      reply.value = statuswordOf(state_);
      reply.size = 2;
      break;
    case cia402::kModesDisplay:
      reply.value = static_cast<uint8_t>(mode_);
      reply.size = 1;
      break;
    case cia402::kActualPosition:
      reply.value = static_cast<uint32_t>(clampToI32(position_, INT32_MIN, INT32_MAX));
      break;
    case cia402::kActualVelocity:
      reply.value = static_cast<uint32_t>(clampToI32(velocity_, INT32_MIN, INT32_MAX));
      break;
    default:
      reply.kind = SdoMessage::Kind::kAbort;
      reply.value = 0x06020000;  // object does not exist
  }
}

void Cia402AxisSim::applyRpdo1(const Cia402Rpdo1& p) {
  const uint16_t cw = p.controlword;
  const bool reset_edge = (cw & cia402::kCwFaultReset) && !(controlword_ & cia402::kCwFaultReset);
  if (state_ == Cia402State::kFault) {
    if (reset_edge && !faults_.stall && !faults_.encoder) state_ = Cia402State::kSwitchOnDisabled;
  } else {
    state_ = nextState(state_, cw);
  }
  if (steering_) {
    const bool new_setpoint = (cw & cia402::kCwNewSetPoint) && !(controlword_ & cia402::kCwNewSetPoint);
    if (new_setpoint && state_ == Cia402State::kOperationEnabled) {
      target_position_ = p.target;
      setpoint_ack_ = true;
    }
    if (!(cw & cia402::kCwNewSetPoint)) setpoint_ack_ = false;
  } else {
    target_velocity_ = p.target;
  }
  controlword_ = cw;
}

void Cia402AxisSim::step(double now_s, CanBus& bus) {
  const double dt = now_s_ < 0.0 ? 0.0 : std::max(0.0, now_s - now_s_);
  now_s_ = now_s;
  if (faults_.silent) {
    velocity_ = 0.0;
    return;
  }
  if (nmt_ == kHeartbeatBootUp) {
    if (!boot_sent_) bus.send(encodeHeartbeat(node_, kHeartbeatBootUp));
    boot_sent_ = true;
    nmt_ = kHeartbeatPreOperational;
  }
  if (heartbeat_ms_ > 0 && now_s >= next_heartbeat_s_) {
    bus.send(encodeHeartbeat(node_, nmt_));
    next_heartbeat_s_ = now_s + heartbeat_ms_ / 1000.0;
  }
  const uint32_t consumer_ms = consumer_ & 0xFFFF;
  if (consumer_ms > 0 && last_host_heartbeat_s_ >= 0.0 && now_s - last_host_heartbeat_s_ > consumer_ms / 1000.0 &&
      nmt_ == kHeartbeatOperational) {
    enterFault(0x8130, bus);  // heartbeat of the host lost: the drive stops by itself
    last_host_heartbeat_s_ = -1.0;
  }
  if (faults_.stall) enterFault(0x7121, bus);
  if (faults_.encoder) enterFault(0x7305, bus);
  const bool enabled = state_ == Cia402State::kOperationEnabled && nmt_ == kHeartbeatOperational;
  if (!steering_) {
    const double accel = profile_acceleration_ > 0 ? profile_acceleration_ : 1e9;
    velocity_ = approach(velocity_, enabled ? target_velocity_ : 0.0, accel * dt);
    position_ += velocity_ * dt;
  } else if (enabled && dt > 0.0) {
    const double speed = profile_velocity_ > 0 ? profile_velocity_ : 1e9;
    const double next = approach(position_, target_position_, speed * dt);
    velocity_ = (next - position_) / dt;
    position_ = next;
  } else {
    velocity_ = 0.0;
  }
}

}  // namespace thorvald_can_devices
