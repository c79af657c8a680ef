#include "thorvald_can_devices/cia401_board.h"

#include "thorvald_can_devices/canopen_protocol.h"

namespace thorvald_can_devices {

Cia401Board::Cia401Board(CanBus* bus, const thorvald_base::IoConfig& config, IoBoardTiming timing)
    : bus_(bus),
      name_(config.name),
      node_(config.id),
      timing_(timing),
      verdict_({timing.confirm_timeout_s, timing.silence_timeout_s}) {
  commanded_ = static_cast<uint8_t>((config.rl0_init_state ? 0x01 : 0) | (config.rl1_init_state ? 0x02 : 0));
}

std::vector<uint32_t> Cia401Board::receiveIds() const {
  const auto n = static_cast<uint32_t>(node_);
  return {canopen_ids::kTpdo1 + n, canopen_ids::kHeartbeat + n};
}

std::vector<uint32_t> Cia401Board::transmitIds() const { return {canopen_ids::kRpdo1 + static_cast<uint32_t>(node_)}; }

void Cia401Board::start(double now_s) {
  now_s_ = now_s;
  verdict_.commanded(now_s);
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
  verdict_.commanded(now_s_);
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
    verdict_.echoed(feedback->outputs);
  }
  verdict_.heard(now_s);
  judge(now_s);
}

bool Cia401Board::answering() const { return verdict_.answering(now_s_) && nmt_state_ == kHeartbeatOperational; }

void Cia401Board::judge(double now_s) {
  verdict_.judge(now_s, commanded_,
                 nmt_state_ == kHeartbeatOperational
                     ? ""
                     : std::string("board ") + nmtStateName(nmt_state_) + " (outputs at their error value)");
}

void Cia401Board::tick(double now_s) {
  now_s_ = now_s;
  // A board that rebooted (boot-up, pre-operational) or was stopped is started again, once a second at most.
  if (verdict_.everHeard() && nmt_state_ != kHeartbeatOperational && now_s - last_nmt_s_ >= 1.0) {
    last_nmt_s_ = now_s;
    bus_->send(encodeNmt(NmtCommand::kStart, node_));
    verdict_.commanded(now_s);
  }
  if (bus_off_) {
    verdict_.doubt("CAN bus off");
    return;
  }
  if (now_s - last_sent_s_ >= timing_.refresh_period_s) send(now_s);
  judge(now_s);
}

thorvald_base::IoBoardStatus Cia401Board::status() const {
  thorvald_base::IoBoardStatus s = verdict_.status(now_s_, commanded_);
  s.answering = answering();
  return s;
}

}  // namespace thorvald_can_devices
