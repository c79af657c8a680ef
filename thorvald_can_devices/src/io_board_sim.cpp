#include "thorvald_can_devices/io_board_sim.h"

#include "thorvald_can_devices/canopen_protocol.h"

namespace thorvald_can_devices {

IoBoardSim::IoBoardSim(const thorvald_base::IoConfig& config) : name_(config.name), node_(config.id) {}

bool IoBoardSim::setFault(const std::string& fault, bool active) {
  if (fault == "silent") {
    silent_ = active;
    if (active) {
      outputs_ = 0;  // unpowered: the relays drop
      state_ = kHeartbeatPreOperational;
      booted_ = false;  // powered again, it boots
    }
    return true;
  }
  if (fault == "stuck") {
    stuck_ = active;
    return true;
  }
  return false;
}

void IoBoardSim::setOutputs(uint8_t value, CanBus& bus) {
  if (stuck_ || value == outputs_) return;
  outputs_ = value;
  bus.send(encodeIoFeedback(node_, {inputs, outputs_}));  // event-driven TPDO1: every change at once
}

void IoBoardSim::boot(double now_s, CanBus& bus) {
  booted_ = true;
  state_ = kHeartbeatPreOperational;
  bus.send(encodeHeartbeat(node_, kHeartbeatBootUp));
  next_heartbeat_s_ = now_s + cia401::kHeartbeatPeriodS;
}

void IoBoardSim::handle(const CanFrame& f, CanBus& bus, double now_s) {
  if (silent_ || f.isError() || f.isExtended() || f.isRemote()) return;
  if (!booted_) boot(now_s, bus);
  const uint32_t id = f.stdId();
  if (id == canopen_ids::kNmt) {
    const auto nmt = decodeNmt(f);
    if (!nmt || (nmt->node != 0 && nmt->node != node_)) return;
    const auto next = nmtStateAfter(nmt->command);
    if (!next) {
      setOutputs(0, bus);
      boot(now_s, bus);  // reset: boots again
      return;
    } else {
      state_ = *next;
    }
    if (state_ != kHeartbeatOperational) setOutputs(0, bus);
    last_rpdo_s_ = now_s;  // the RPDO timeout counts from the start
    return;
  }
  if (id == canopen_ids::kRpdo1 + static_cast<uint32_t>(node_) && state_ == kHeartbeatOperational) {
    const auto outputs = decodeIoOutputs(f);
    if (!outputs) return;  // a malformed PDO is ignored (CiA 301 would send an EMCY)
    last_rpdo_s_ = now_s;
    setOutputs(*outputs, bus);
  }
}

void IoBoardSim::step(double now_s, CanBus& bus) {
  if (silent_) return;
  if (!booted_) boot(now_s, bus);
  if (state_ == kHeartbeatOperational && now_s - last_rpdo_s_ > cia401::kRpdoTimeoutS) {
    setOutputs(0, bus);  // error mode (0x6206): the host went quiet, the outputs go to their error value, off
  }
  if (now_s >= next_heartbeat_s_) {
    next_heartbeat_s_ = now_s + cia401::kHeartbeatPeriodS;
    bus.send(encodeHeartbeat(node_, state_));
  }
  if (state_ == kHeartbeatOperational && now_s >= next_tpdo_s_) {
    next_tpdo_s_ = now_s + cia401::kTpdoPeriodS;
    bus.send(encodeIoFeedback(node_, {inputs, outputs_}));
  }
}

}  // namespace thorvald_can_devices
