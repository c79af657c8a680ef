#pragma once

#include <atomic>
#include <functional>
#include <mutex>
#include <string>
#include <thread>

#include "greenhouse_rail_nav/uv_mission.h"

namespace greenhouse_rail_nav {

/// Runs a UvMission on a thread of its own as the operator starts and stops it (the node's ~start and ~stop
/// services, autostart), and decides what follows a run: a run that throws ends "aborted" with the robot stopped
/// and its lights off; with exit_when_done, a run that was not preempted ends the process. start(), stop() and
/// running() may be called from any thread; the hooks run on the mission's thread.
class UvMissionRunner {
 public:
  struct Hooks {
    /// A run threw: the error's text, before the robot is stopped.
    std::function<void(const std::string& error)> error;
    /// A run ended with this outcome ("done", "aborted", "preempted"): save progress, report.
    std::function<void(const std::string& outcome)> finished;
    /// After `finished`, when the process should end (exit_when_done and the run was not preempted).
    std::function<void()> exit;
  };

  UvMissionRunner(UvMission& mission, MissionIO& io, bool exit_when_done, Hooks hooks);
  /// Preempts a run and waits for its thread (shutdown()).
  ~UvMissionRunner();

  /// Starts a run: "started", or "already running" (nothing changes); "shutting down" after shutdown().
  std::string start();
  /// Asks the mission to stop (preemption; a later start() resumes at the first set not treated). The operator's
  /// answer; *was_running says whether a run was going.
  std::string stop(bool* was_running);
  bool running() const { return running_; }
  /// Preempts a run and waits for its thread to end; no run starts after it.
  void shutdown();

 private:
  void runOnce();

  UvMission& mission_;
  MissionIO& io_;
  bool exit_when_done_;
  Hooks hooks_;
  std::atomic<bool> running_{false};
  std::mutex worker_mutex_;
  std::thread worker_;
  bool shut_down_ = false;  // guarded by worker_mutex_
};

}  // namespace greenhouse_rail_nav
