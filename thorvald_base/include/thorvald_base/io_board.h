#pragma once

#include <cstdint>
#include <string>

namespace thorvald_base {

/// What base_driver knows of one relay board (`io.ioN` of the robot file).
struct IoBoardStatus {
  bool answering = false;     ///< heartbeat and output echo arrive, node operational
  bool state_unknown = true;  ///< the outputs' real state is in doubt (not confirmed, or the board went quiet)
  uint8_t commanded = 0;      ///< output bits last commanded (bit i = output i)
  uint8_t confirmed = 0;      ///< output bits last echoed by the board (valid while !state_unknown)
  std::string why;            ///< why the state is unknown, "" when it is known
  double age_s = -1.0;        ///< time since the board's last frame [s]; -1 before the first
};

/// A relay board: switches its outputs on command and says whether the switching was confirmed. Implemented by a
/// device of the hardware plugin (thorvald_can_devices' CiA 401 board); base_driver owns it and calls update()
/// every control cycle after the hardware's poll().
class IoBoard {
 public:
  virtual ~IoBoard() = default;
  virtual const std::string& name() const = 0;  ///< ioN of the robot file
  virtual int outputCount() const = 0;          ///< outputs 0 .. outputCount() - 1
  /// Commands output `output` on or off; the board's echo confirms it later. Out-of-range outputs are ignored.
  virtual void command(int output, bool on) = 0;
  virtual void update(double now_s) = 0;
  virtual IoBoardStatus status() const = 0;
};

}  // namespace thorvald_base
