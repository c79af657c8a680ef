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

/// How long the host waits for a relay board before its outputs' state is in doubt.
struct IoBoardTimeouts {
  double confirm_timeout_s = 0.25;  ///< a command not echoed by the board within this puts the state in doubt [s]
  double silence_timeout_s = 0.35;  ///< no frame from the board for this long: board lost, state in doubt [s]
};

/// The host's verdict on a relay board's outputs, for an IoBoard implementation: unknown until the board echoes the
/// command, when the echo does not match the command within the confirm timeout, when the board is silent, and while
/// the board reports a fault of its own; known again only when the board echoes the command. Within the confirm
/// timeout a changing output keeps its last verdict.
class IoBoardVerdict {
 public:
  explicit IoBoardVerdict(IoBoardTimeouts timeouts = {}) : t_(timeouts) {}

  void commanded(double now_s) { commanded_s_ = now_s; }  ///< the commanded outputs changed at now_s
  void heard(double now_s) {                              ///< a frame of the board arrived at now_s
    heard_ = true;
    last_frame_s_ = now_s;
  }
  void echoed(uint8_t outputs) {  ///< the board echoed its outputs
    echoed_ = outputs;
    echo_heard_ = true;
  }
  bool answering(double now_s) const { return heard_ && now_s - last_frame_s_ <= t_.silence_timeout_s; }
  /// Judges the outputs at now_s against `commanded`; `fault` non-empty: the board answers but its outputs are not
  /// driven (e.g. not operational), and says why.
  void judge(double now_s, uint8_t commanded, const std::string& fault = "") {
    if (!answering(now_s)) {
      unknown_ = true;
      why_ = heard_ ? "board silent for " + std::to_string(now_s - last_frame_s_).substr(0, 5) + " s"
                    : "board never answered";
    } else if (!fault.empty()) {
      unknown_ = true;
      why_ = fault;
    } else if (echo_heard_ && echoed_ == commanded) {
      unknown_ = false;
      why_.clear();
    } else if (now_s - commanded_s_ > t_.confirm_timeout_s) {
      unknown_ = true;
      why_ = "outputs " + hexBits(commanded) + " commanded, board echoes " +
             (echo_heard_ ? hexBits(echoed_) : std::string("nothing"));
    }
  }
  /// The status with this verdict (answering, state_unknown, confirmed, why, age_s) and `commanded`.
  IoBoardStatus status(double now_s, uint8_t commanded) const {
    IoBoardStatus s;
    s.answering = answering(now_s);
    s.state_unknown = unknown_;
    s.commanded = commanded;
    s.confirmed = echoed_;
    s.why = why_;
    s.age_s = heard_ ? now_s - last_frame_s_ : -1.0;
    return s;
  }
  /// Puts the state in doubt for a reason of the host's own (e.g. its bus is off), until the next judge().
  void doubt(const std::string& why) {
    unknown_ = true;
    why_ = why;
  }
  bool everHeard() const { return heard_; }  ///< a frame of the board has arrived
  bool unknown() const { return unknown_; }
  const std::string& why() const { return why_; }

  static std::string hexBits(uint8_t v) {
    static const char* digits = "0123456789ABCDEF";
    return std::string("0x") + digits[v >> 4] + digits[v & 0x0F];
  }

 private:
  IoBoardTimeouts t_;
  bool heard_ = false, echo_heard_ = false, unknown_ = true;
  uint8_t echoed_ = 0;
  double last_frame_s_ = -1e9, commanded_s_ = 0.0;
  std::string why_ = "no echo from the board yet";
};

}  // namespace thorvald_base
