#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace thorvald_state_machine {

/// One finished state and where its machine went next.
struct TransitionRecord {
  double stamp_s = 0.0;  ///< time the state finished [s], on the machine's clock
  std::string state;     ///< path of the finished state, outermost first, joined by '/'
  std::string outcome;   ///< outcome it returned
  std::string next;      ///< path of the next state, or "-> <machine outcome>" when a machine finished
};

/// A snapshot of a machine for introspection (what SMACH's viewer shows).
struct StatusSnapshot {
  std::string machine;                    ///< name of the outermost machine
  std::string active_state;               ///< path of the active state joined by '/', empty when idle
  std::string last_outcome;               ///< outcome of the last finished state (or machine)
  bool running = false;                   ///< the machine is executing
  bool preempt_requested = false;         ///< a preemption was requested and not yet served
  std::uint32_t transitions = 0;          ///< transitions since the last start
  std::vector<TransitionRecord> history;  ///< most recent transitions, oldest first
};

/// Joins a state path with '/'.
std::string joinPath(const std::vector<std::string>& path);

}  // namespace thorvald_state_machine
