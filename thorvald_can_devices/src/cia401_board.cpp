#include "thorvald_can_devices/cia401_board.h"

#include <cstdio>

#include "thorvald_can_devices/canopen_protocol.h"

namespace thorvald_can_devices {
namespace {
std::string hexByte(uint8_t v) {
  char buf[8];
  std::snprintf(buf, sizeof(buf), "0x%02X", v);
  return buf;
}
}  // namespace

Cia401Board::Cia401Board(CanBus* bus, const thorvald_base::IoConfig& config, IoBoardTiming timing)
    : bus_(bus), name_(config.name), node_(config.id), timing_(timing) {
  commanded_ = static_cast<uint8_t>((config.rl0_init_state ? 0x01 : 0) | (config.rl1_init_state ? 0x02 : 0));
}

std::vector<uint32_t> Cia401Board::receiveIds() const {
  const auto n = static_cast<uint32_t>(node_);
  return {canopen_ids::kTpdo1 + n, canopen_ids::kHeartbeat + n};
}

std::vector<uint32_t> Cia401Board::transmitIds() const { return {canopen_ids::kRpdo1 + static_cast<uint32_t>(node_)}; }

void Cia401Board::start(double now_s) {
  now_s_ = now_s;
  commanded_s_ = now_s;
  last_nmt_s_ = now_s;
  bus_->send(encodeNmt(NmtCommand::kStart, node_));
  send(now_s);
}

void Cia401Board::send(double now_s) {
  bus_->send(encodeIoOutputs(node_, commanded_));
  last_sent_s_ = now_s;
}

void Cia401Board::command(int output, bool on) {
  if (output < 0 || output >= cia401::kOutputs) return;
  const auto bit = static_cast<uint8_t>(1u << output);
  const uint8_t next = on ? static_cast<uint8_t>(commanded_ | bit) : static_cast<uint8_t>(commanded_ & ~bit);
  if (next == commanded_) return;
  commanded_ = next;
  commanded_s_ = now_s_;
  send(now_s_);  // at once: the lamps' relay must not wait for the next cycle
}

void Cia401Board::handle(const CanFrame& f, double now_s) {
  now_s_ = now_s;
  const uint32_t base = f.stdId() - static_cast<uint32_t>(node_);
  if (base == canopen_ids::kHeartbeat) {
    const auto state = decodeHeartbeat(f);
    if (!state) {
      ++malformed_;
      return;
    }
    nmt_state_ = *state;
  } else {
    const auto feedback = decodeIoFeedback(f);
    if (!feedback) {
      ++malformed_;
      return;
    }
    echoed_ = feedback->outputs;
    echo_heard_ = true;
  }
  heard_ = true;
  last_frame_s_ = now_s;
  judge(now_s);
}

bool Cia401Board::answering() const {
  return heard_ && now_s_ - last_frame_s_ <= timing_.silence_timeout_s && nmt_state_ == kHeartbeatOperational;
}

void Cia401Board::judge(double now_s) {
  if (!heard_ || now_s - last_frame_s_ > timing_.silence_timeout_s) {
    unknown_ = true;
    why_ = heard_ ? "board silent for " + std::to_string(now_s - last_frame_s_).substr(0, 5) + " s"
                  : "board never answered";
    return;
  }
  if (nmt_state_ != kHeartbeatOperational) {
    unknown_ = true;
    why_ = std::string("board ") + nmtStateName(nmt_state_) + " (outputs at their error value)";
    return;
  }
  if (echo_heard_ && echoed_ == commanded_) {
    unknown_ = false;
    why_.clear();
    return;
  }
  if (now_s - commanded_s_ > timing_.confirm_timeout_s) {
    unknown_ = true;
    why_ = "outputs " + hexByte(commanded_) + " commanded, board echoes " +
           (echo_heard_ ? hexByte(echoed_) : std::string("nothing"));
  }
  // Within the confirm timeout a changing output keeps its last judgement.
}

void Cia401Board::tick(double now_s) {
  now_s_ = now_s;
  // A board that rebooted (boot-up, pre-operational) or was stopped is started again, once a second at most.
  if (heard_ && nmt_state_ != kHeartbeatOperational && now_s - last_nmt_s_ >= 1.0) {
    last_nmt_s_ = now_s;
    bus_->send(encodeNmt(NmtCommand::kStart, node_));
    commanded_s_ = now_s;
  }
  if (bus_off_) {
    unknown_ = true;
    why_ = "CAN bus off";
    return;
  }
  if (now_s - last_sent_s_ >= timing_.refresh_period_s) send(now_s);
  judge(now_s);
}

thorvald_base::IoBoardStatus Cia401Board::status() const {
  thorvald_base::IoBoardStatus s;
  s.answering = answering();
  s.state_unknown = unknown_;
  s.commanded = commanded_;
  s.confirmed = echoed_;
  s.why = why_;
  s.age_s = heard_ ? now_s_ - last_frame_s_ : -1.0;
  return s;
}

}  // namespace thorvald_can_devices
