#include "cotton_harvester_sim/stack_run_report.h"

#include <exception>

namespace cotton_harvester {
namespace sim {

bool StackRunReport::onStatus(bool running, double sim_time_s) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!running || figures_.started) return false;
  figures_.started = true;
  figures_.started_at_s = sim_time_s;
  return true;
}

void StackRunReport::onMetrics(const std::string& message,
                               const std::vector<std::pair<std::string, std::string>>& values) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (const auto& [key, text] : values) {
    try {
      figures_.values[key] = std::stod(text);
    } catch (const std::exception&) {
      // "n/a" ratios: not needed
    }
  }
  const std::string ended = "ended: ";
  if (figures_.started && message.compare(0, ended.size(), ended) == 0) figures_.outcome = message.substr(ended.size());
}

StackRunState StackRunReport::check(double sim_time_s, double waited_wall_s, double time_limit_s,
                                    double start_timeout_s) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!figures_.outcome.empty()) return StackRunState::kEnded;
  if (figures_.started && sim_time_s - figures_.started_at_s > time_limit_s) {
    figures_.outcome = "time_limit";
    return StackRunState::kEnded;
  }
  if (!figures_.started && waited_wall_s > start_timeout_s) return StackRunState::kNoStart;
  return figures_.started ? StackRunState::kRunning : StackRunState::kWaiting;
}

StackFigures StackRunReport::figures() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return figures_;
}

}  // namespace sim
}  // namespace cotton_harvester
