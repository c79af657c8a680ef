#pragma once

#include <condition_variable>
#include <mutex>
#include <thread>

namespace thorvald_common {

/// Orderly stop on SIGINT and SIGTERM, with a deadline.
///
/// The handlers set a flag and call `on_signal` (e.g. `ros::requestShutdown`, which only sets roscpp's flag and is
/// what roscpp's own SIGINT handler calls): a node's loop ends, and so does roscpp's wait for an unreachable master.
/// Some calls cannot be interrupted that way (a request to a master that accepted the connection and never
/// answers): if this object still exists `grace_s` after the first signal, a watchdog thread ends the process with
/// `_exit(0)` after saying so on stderr. So the process stops within `grace_s` (plus a poll cycle) in every state.
/// One instance per process; create it right after `ros::init(..., ros::init_options::NoSigintHandler)` and keep
/// it until the end of `main`.
class StopSignals {
 public:
  /// `on_signal` runs inside the signal handler: it must be async-signal-safe. `grace_s` [s] > 0.
  StopSignals(void (*on_signal)(), double grace_s);
  ~StopSignals();
  StopSignals(const StopSignals&) = delete;
  StopSignals& operator=(const StopSignals&) = delete;

  /// True once SIGINT or SIGTERM arrived.
  static bool requested();

  /// Replaces what the handler calls (nullptr: nothing, the flag alone), e.g. once a node's own loop watches
  /// `requested()` and must still publish before roscpp shuts down.
  void setOnSignal(void (*on_signal)());

 private:
  void watch();

  double grace_s_;
  std::mutex mutex_;
  std::condition_variable finished_cv_;
  bool finished_ = false;
  std::thread watchdog_;
};

}  // namespace thorvald_common
