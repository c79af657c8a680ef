#include "cotton_harvester_sim/harvest_scorer.h"

#include <cmath>
#include <cstdio>
#include <utility>

namespace cotton_harvester {
namespace sim {

RoverTruth truthOf(const RoverSim& sim) {
  RoverTruth truth;
  truth.bolls = sim.bolls();
  truth.bolls_captured = sim.bollsCaptured();
  truth.rover_position = sim.roverPosition();
  truth.time_s = sim.time();
  return truth;
}

HarvestScorer::HarvestScorer(std::vector<bool> reachable, const Eigen::Vector3d& start_position)
    : reachable_(std::move(reachable)), start_position_(start_position) {}

HarvestScore HarvestScorer::score(const StackFigures& stack, const RoverTruth& truth) const {
  HarvestScore s;
  s.outcome = stack.outcome;
  const auto value = [&stack](const char* key) {
    const auto it = stack.values.find(key);
    return it == stack.values.end() ? 0.0 : it->second;
  };
  control::HarvestCounts& counts = s.counts;
  counts.detected = static_cast<int>(value("detected"));
  counts.reached = static_cast<int>(value("reached"));
  counts.skipped = static_cast<int>(value("skipped"));
  counts.pick_attempts = static_cast<int>(value("pick_attempts"));
  s.machine_picked = static_cast<int>(value("picked"));
  s.ee_fallback_frames = value("ee_fallback_frames");
  s.frames_without_end_effector = value("frames_without_end_effector");
  // The machine's own run time (its clock is the simulated /clock); at the time limit, since it started.
  const auto run_time = stack.values.find("time_s");
  counts.time_s = s.outcome != "time_limit" && run_time != stack.values.end()
                      ? run_time->second
                      : truth.time_s - (stack.started ? stack.started_at_s : 0.0);
  counts.bolls_present = static_cast<int>(truth.bolls.size());
  counts.picked = truth.bolls_captured;
  counts.distance_m = (truth.rover_position - start_position_).norm();
  s.metrics = control::computeMetrics(counts);
  for (std::size_t i = 0; i < reachable_.size(); ++i) {
    s.reachable += reachable_[i];
    s.reachable_picked += reachable_[i] && i < truth.bolls.size() && truth.bolls[i].captured;
  }
  for (std::size_t i = 0; i < truth.bolls.size(); ++i) {
    if (truth.bolls[i].captured) continue;
    s.missed.push_back({i, truth.bolls[i], i < reachable_.size() && reachable_[i]});
  }
  return s;
}

std::string summaryLine(const std::string& node, const HarvestScore& s, const SimRunFigures& run) {
  const control::HarvestCounts& c = s.counts;
  const control::HarvestMetrics& m = s.metrics;
  char text[1024];
  std::snprintf(
      text, sizeof(text),
      "%s: %s; bolls %d (reachable %d), detected %d, reached %d, picked %d (machine: %d); time %.1f s, CT %.1f s, "
      "ASR %.1f %%, DP %.1f %%, MRR %.1f %%, OV %.2f cm/s; %d frames; %.2fx real time; lockstep timeouts: %d drive, "
      "%d camera; end effector from calibration %.0f, missing %.0f",
      node.c_str(), s.outcome.c_str(), c.bolls_present, s.reachable, c.detected, c.reached, c.picked, s.machine_picked,
      c.time_s, m.cycle_time_s.value_or(0.0), m.action_success_pct.value_or(0.0),
      m.detection_performance_pct.value_or(0.0), m.reaching_ratio_pct.value_or(0.0), m.operation_velocity_cm_s,
      run.frames, run.wall_s > 0.0 ? run.sim_s / run.wall_s : 0.0, run.lockstep_timeouts, run.camera_lockstep_timeouts,
      s.ee_fallback_frames, s.frames_without_end_effector);
  return text;
}

std::vector<std::string> missedBollLines(const std::string& node, const HarvestScore& s) {
  std::vector<std::string> lines;
  for (const HarvestScore::Missed& missed : s.missed) {
    const BollTruth& b = missed.boll;
    char text[256];
    std::snprintf(text, sizeof(text), "%s: missed boll %zu (plant %d, x %.2f y %.2f z %.2f)%s; nozzle closest %.1f cm",
                  node.c_str(), missed.index, b.plant, b.centre.x(), b.centre.y(), b.centre.z(),
                  missed.reachable ? "" : " unreachable",
                  std::isfinite(b.closest_vacuum_m) ? 100.0 * b.closest_vacuum_m : -1.0);
    lines.push_back(text);
  }
  return lines;
}

}  // namespace sim
}  // namespace cotton_harvester
