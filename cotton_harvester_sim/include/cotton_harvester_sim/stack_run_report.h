#pragma once

#include <map>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace cotton_harvester {
namespace sim {

/// What the harvest stack has told about its run so far (a copy, see StackRunReport).
struct StackFigures {
  bool started = false;                  ///< the machine ran
  double started_at_s = 0.0;             ///< simulated time of its first running status [s]
  std::string outcome;                   ///< "finished", "time_limit", ...; empty while the run goes on
  std::map<std::string, double> values;  ///< its last metrics (detected, reached, time_s, ...)
};

/// Where a harvest run through the nodes stands, for the simulator that drives it.
enum class StackRunState {
  kWaiting,  ///< the machine has not started yet
  kRunning,  ///< it runs
  kEnded,    ///< it reported the end of its run, or it hit the time limit (outcome "time_limit")
  kNoStart   ///< it did not start within the start timeout
};

/// What the harvest stack tells about its run through its own status and metrics topics (nothing of the simulator's
/// truth), and when the run counts as over. ROS-free; thread-safe (the topics' callbacks and the simulation loop
/// share it).
class StackRunReport {
 public:
  /// The machine's status at simulated time sim_time_s [s]; true when this is its first running status.
  bool onStatus(bool running, double sim_time_s);
  /// The stack's metrics: each value that reads as a number is kept (others, such as "n/a" ratios, are skipped); a
  /// message "ended: <outcome>" after the start ends the run with that outcome.
  void onMetrics(const std::string& message, const std::vector<std::pair<std::string, std::string>>& values);
  /// The run's state at simulated time sim_time_s [s] after waited_wall_s [s] of wall time: ended when the stack said
  /// so or when time_limit_s [s] of simulated time passed since the start (which sets the outcome "time_limit"); no
  /// start when the machine did not start within start_timeout_s [s] of wall time.
  StackRunState check(double sim_time_s, double waited_wall_s, double time_limit_s, double start_timeout_s);
  StackFigures figures() const;

 private:
  mutable std::mutex mutex_;
  StackFigures figures_;
};

}  // namespace sim
}  // namespace cotton_harvester
