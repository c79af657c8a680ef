#pragma once

#include <string>
#include <vector>

namespace thorvald_twist_mux {

/// One velocity input or one lock of the multiplexer, as twist_mux's `topics`/`locks` lists describe it.
struct MuxEntry {
  std::string name;   ///< unique within its list; used in status and diagnostics
  std::string topic;  ///< topic name, resolved in the node's namespace
  double timeout_s;   ///< [s] inputs: age after which the input stops competing; locks: watchdog; 0 = never
  int priority;       ///< 0..255, higher wins; a lock masks inputs of strictly lower priority
  bool stamped;       ///< inputs only: geometry_msgs/TwistStamped instead of Twist
};

/// The full multiplexer configuration: inputs in the order listed (ties go to the first) and locks.
struct MuxConfig {
  std::vector<MuxEntry> inputs;
  std::vector<MuxEntry> locks;
};

/// Returns an empty string when `config` is usable, otherwise one message naming the bad entry, the key and what
/// was expected (e.g. "topics[1] (nav): timeout is -1, expected >= 0").
std::string validateMuxConfig(const MuxConfig& config);

}  // namespace thorvald_twist_mux
