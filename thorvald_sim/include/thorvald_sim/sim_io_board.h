#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <string>

#include "thorvald_base/io_board.h"
#include "thorvald_base/robot_config.h"

namespace thorvald_sim {

/// Timing and faults of a simulated relay board (SimHardware's `~sim_io_*` parameters). Fault times count from the
/// board's first update (base_driver's first control cycle); a negative time never comes.
struct SimIoBoardSettings {
  double echo_delay_s = 0.02;               ///< a switched output is echoed to the host this long after the command [s]
  double echo_period_s = 0.1;               ///< the board also echoes its outputs this often (its heartbeat) [s]
  double silent_after_s = -1.0;             ///< from then on the board is unpowered: outputs off, no echo [s]
  double stuck_after_s = -1.0;              ///< from then on the relays keep their state whatever is commanded [s]
  thorvald_base::IoBoardTimeouts timeouts;  ///< the host's confirm and silence timeouts (as the CAN board's)
};

/// A relay board of the robot file (`io.ioN`) for a base simulated by thorvald_sim: the relays switch as soon as
/// they are commanded and the board echoes them after echo_delay_s (and every echo_period_s), so the host confirms
/// them as it would on CAN; the host's verdict is thorvald_base's IoBoardVerdict. Faults: silent (unpowered, outputs
/// off, nothing echoed: the state becomes unknown after the silence timeout) and stuck (the relays keep their state:
/// the echo contradicts a new command and the state becomes unknown after the confirm timeout). The relays' real
/// state goes to `on_outputs` on every change, for the simulator's truth.
class SimIoBoard : public thorvald_base::IoBoard {
 public:
  SimIoBoard(const thorvald_base::IoConfig& config, SimIoBoardSettings settings);

  const std::string& name() const override { return name_; }
  int outputCount() const override { return 8; }
  void command(int output, bool on) override;
  void update(double now_s) override;
  thorvald_base::IoBoardStatus status() const override { return verdict_.status(now_s_, commanded_); }

  uint8_t outputs() const { return outputs_; }  ///< the relays' real state (bit i = output i)
  bool silent() const { return silent_; }
  bool stuck() const { return stuck_; }
  std::function<void(uint8_t)> on_outputs;  ///< called with the relays' real state on every change

 private:
  void setOutputs(uint8_t value);
  void echo(double now_s);

  struct Echo {
    double due_s;
    uint8_t outputs;
  };
  std::string name_;
  SimIoBoardSettings settings_;
  thorvald_base::IoBoardVerdict verdict_;
  uint8_t commanded_ = 0, outputs_ = 0;
  bool started_ = false, silent_ = false, stuck_ = false;
  double start_s_ = 0.0, now_s_ = 0.0, next_echo_s_ = 0.0;
  std::deque<Echo> echoes_;  ///< on their way to the host
};

}  // namespace thorvald_sim
