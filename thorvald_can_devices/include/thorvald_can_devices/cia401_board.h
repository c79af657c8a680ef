#pragma once

#include <string>
#include <vector>

#include "thorvald_base/io_board.h"
#include "thorvald_base/robot_config.h"
#include "thorvald_can_devices/can_device.h"
#include "thorvald_can_devices/cia401_protocol.h"

namespace thorvald_can_devices {

/// Timing of the host side of a relay board.
struct IoBoardTiming {
  double confirm_timeout_s = 0.25;  ///< a command not echoed by the board within this puts the state in doubt [s]
  double silence_timeout_s = 0.35;  ///< no heartbeat or TPDO1 for this long: board lost, state in doubt [s]
  double refresh_period_s = 0.1;    ///< RPDO1 is repeated this often (the board's RPDO timeout is 0.5 s) [s]
};

/// Host side of a CiA 401 relay board (`io.ioN`, node = its id): starts it with NMT, writes the commanded outputs
/// with RPDO1 at once and every refresh period, and confirms them from the board's TPDO1 echo. The outputs' state is
/// unknown until the first matching echo, when an echo does not match within the confirm timeout, and when the board
/// stops answering or leaves NMT operational; it becomes known again only when the board echoes the command.
class Cia401Board : public CanDevice, public thorvald_base::IoBoard {
 public:
  Cia401Board(CanBus* bus, const thorvald_base::IoConfig& config, IoBoardTiming timing = {});

  // CanDevice
  std::string label() const override { return name_ + " (relay board, node " + std::to_string(node_) + ")"; }
  std::vector<uint32_t> receiveIds() const override;
  std::vector<uint32_t> transmitIds() const override;
  void start(double now_s) override;
  void handle(const CanFrame& frame, double now_s) override;
  void tick(double now_s) override;
  bool operational() const override { return answering() && !verdict_.unknown(); }
  unsigned long malformed() const override { return malformed_; }

  // thorvald_base::IoBoard
  const std::string& name() const override { return name_; }
  int outputCount() const override { return cia401::kOutputs; }
  void command(int output, bool on) override;
  void update(double) override {}
  thorvald_base::IoBoardStatus status() const override;

  int node() const { return node_; }

 private:
  bool answering() const;
  void send(double now_s);
  void judge(double now_s);

  CanBus* bus_;
  std::string name_;
  int node_;
  IoBoardTiming timing_;
  thorvald_base::IoBoardVerdict verdict_;  ///< echo and silence judged as for every relay board
  uint8_t commanded_ = 0;
  uint8_t nmt_state_ = kHeartbeatBootUp;
  double now_s_ = 0.0, last_sent_s_ = -1e9, last_nmt_s_ = -1e9;
  unsigned long malformed_ = 0;
};

}  // namespace thorvald_can_devices
