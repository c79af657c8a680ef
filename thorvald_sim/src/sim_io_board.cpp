#include "thorvald_sim/sim_io_board.h"

namespace thorvald_sim {

SimIoBoard::SimIoBoard(const thorvald_base::IoConfig& config, SimIoBoardSettings settings)
    : name_(config.name), settings_(settings), verdict_(settings.timeouts) {
  commanded_ = static_cast<uint8_t>((config.rl0_init_state ? 0x01 : 0) | (config.rl1_init_state ? 0x02 : 0));
}

void SimIoBoard::setOutputs(uint8_t value) {
  if (value == outputs_) return;
  outputs_ = value;
  if (on_outputs) on_outputs(outputs_);
}

void SimIoBoard::echo(double now_s) {
  echoes_.push_back({now_s + settings_.echo_delay_s, outputs_});
  next_echo_s_ = now_s + settings_.echo_period_s;
}

void SimIoBoard::command(int output, bool on) {
  if (output < 0 || output >= outputCount()) return;
  const auto bit = static_cast<uint8_t>(1u << output);
  const uint8_t next = on ? static_cast<uint8_t>(commanded_ | bit) : static_cast<uint8_t>(commanded_ & ~bit);
  if (next == commanded_) return;
  commanded_ = next;
  verdict_.commanded(now_s_);
  if (!started_ || silent_) return;
  if (!stuck_) setOutputs(commanded_);
  echo(now_s_);  // the board answers every write, a stuck one with the relays' real state
}

void SimIoBoard::update(double now_s) {
  now_s_ = now_s;
  if (!started_) {  // powered up with the host: takes the commanded (initial) outputs and echoes them
    started_ = true;
    start_s_ = now_s;
    verdict_.commanded(now_s);
    if (on_outputs) on_outputs(outputs_);
    setOutputs(commanded_);
    echo(now_s);
  }
  const double t = now_s - start_s_;
  if (!silent_ && settings_.silent_after_s >= 0.0 && t >= settings_.silent_after_s) {
    silent_ = true;
    echoes_.clear();
    setOutputs(0);  // unpowered: the relays drop out
  }
  if (settings_.stuck_after_s >= 0.0 && t >= settings_.stuck_after_s) stuck_ = true;
  if (!silent_) {
    if (now_s >= next_echo_s_) echo(now_s);
    while (!echoes_.empty() && echoes_.front().due_s <= now_s) {
      verdict_.heard(echoes_.front().due_s);
      verdict_.echoed(echoes_.front().outputs);
      echoes_.pop_front();
    }
  }
  verdict_.judge(now_s, commanded_);
}

}  // namespace thorvald_sim
