#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "thorvald_base/base_hardware.h"

namespace thorvald_base {

/// Bounds of the relay per control cycle.
struct CanRelayOptions {
  int max_sent_per_cycle = 20;       ///< frames from users written to the bus per cycle at most
  int max_received_per_cycle = 200;  ///< frames from the bus handed to users per cycle at most
};

/// What the relay did since it started, for diagnostics.
struct CanRelayCounters {
  unsigned long sent = 0;              ///< user frames written to the bus
  unsigned long received = 0;          ///< bus frames handed to users
  unsigned long received_dropped = 0;  ///< bus frames over the per-cycle bound, never handed to users
  unsigned long refused = 0;           ///< user frames refused: id not allowed, or refused by the hardware
  unsigned long dropped = 0;           ///< user frames dropped: relay muted, or over the per-cycle bound
  /// Refusals per sender (caller id); past CanRelay::kMaxSenders senders the rest count as "(other senders)".
  std::map<std::string, unsigned long> refused_by;
};

/// What became of one frame a user offered.
struct RelayVerdict {
  enum class Kind {
    kSent,            ///< written to the bus
    kMuted,           ///< dropped: the relay is muted
    kOverCycleBound,  ///< dropped: max_sent_per_cycle frames were already sent this cycle
    kRefused,         ///< refused: not in the allow-list, or the hardware refused it (`why`)
  };
  Kind kind = Kind::kSent;
  std::string why;                        ///< kRefused: the reason
  unsigned long refused_from_sender = 0;  ///< kRefused: refusals counted for this sender so far (this one included)
};

/// base_driver's relay of CAN frames between users (can_frames_device_t / _r) and implements on the base's bus: it
/// decides which user frames reach the bus (the allow-list, muting, a bound per cycle), how many bus frames reach
/// users per cycle, and counts all of it. The allow-list holds no id of the base (relayAllowList); the hardware
/// checks each frame once more. Not thread-safe: base_driver's one spinner calls everything.
class CanRelay {
 public:
  /// Most senders whose refusals are counted one by one.
  static constexpr size_t kMaxSenders = 32;

  /// `hardware` must outlive the relay. Throws ConfigError when a bound is below 1.
  CanRelay(BaseHardware& hardware, std::set<uint32_t> allowed, CanRelayOptions options);

  /// A frame from user `sender`: written to the bus when the relay is not muted, the cycle's bound is not reached,
  /// its id is allowed and the hardware takes it.
  RelayVerdict offer(const std::string& sender, const CanFrameData& frame);
  /// Called once per control cycle: the frames from the bus for users (at most max_received_per_cycle, the rest
  /// counted as dropped), and a new cycle for the bound on user frames.
  std::vector<CanFrameData> cycle();

  void setMuted(bool muted) { muted_ = muted; }
  bool muted() const { return muted_; }
  const std::set<uint32_t>& allowed() const { return allowed_; }
  const CanRelayOptions& options() const { return options_; }
  const CanRelayCounters& counters() const { return counters_; }

 private:
  RelayVerdict refuse(const std::string& sender, std::string why);

  BaseHardware& hardware_;
  std::set<uint32_t> allowed_;
  CanRelayOptions options_;
  bool muted_ = false;
  int sent_this_cycle_ = 0;
  CanRelayCounters counters_;
};

}  // namespace thorvald_base
