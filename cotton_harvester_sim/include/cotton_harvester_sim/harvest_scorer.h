#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "cotton_harvester/control/harvest_metrics.h"
#include "cotton_harvester_sim/rover_sim.h"
#include "cotton_harvester_sim/stack_run_report.h"

namespace cotton_harvester {
namespace sim {

/// The simulator's truth at the end of a run, as the scorer reads it.
struct RoverTruth {
  std::vector<BollTruth> bolls;
  int bolls_captured = 0;                                    ///< bolls the vacuum took
  Eigen::Vector3d rover_position = Eigen::Vector3d::Zero();  ///< world [m]
  double time_s = 0.0;                                       ///< simulated time [s]
};

/// The truth of a simulated rover now.
RoverTruth truthOf(const RoverSim& sim);

/// How the simulation itself ran (not scored, reported beside the score).
struct SimRunFigures {
  double sim_s = 0.0;   ///< simulated time the run took [s]
  double wall_s = 0.0;  ///< wall time it took [s]
  int frames = 0;       ///< camera frames rendered
  std::size_t serial_rejected_bytes = 0;
  int lockstep_timeouts = 0, camera_lockstep_timeouts = 0;
};

/// The run's figures: what the vacuum took (truth) over the time the machine ran, with the stack's own counts.
struct HarvestScore {
  std::string outcome;  ///< the stack's ("finished", ...) or "time_limit"
  control::HarvestCounts counts;
  control::HarvestMetrics metrics;
  int reachable = 0;                         ///< bolls the arm can reach on the stretch scored
  int reachable_picked = 0;                  ///< of those, taken by the vacuum
  int machine_picked = 0;                    ///< bolls the machine judged picked
  double ee_fallback_frames = 0.0;           ///< the machine's frames with the arm's calibrated position
  double frames_without_end_effector = 0.0;  ///< the machine's frames without the end effector
  /// The bolls the vacuum did not take.
  struct Missed {
    std::size_t index = 0;  ///< in RoverTruth::bolls
    BollTruth boll;
    bool reachable = false;
  };
  std::vector<Missed> missed;
};

/// The scorer of a harvest run through the nodes, the only part that reads the simulator's truth: counts the bolls
/// picked and missed against what the stack reported (StackFigures). ROS-free.
class HarvestScorer {
 public:
  /// reachable: per boll, whether the arm can reach it on the stretch scored (reachableBolls); start_position: the
  /// rover's at the start, world [m].
  HarvestScorer(std::vector<bool> reachable, const Eigen::Vector3d& start_position);

  /// The stack's counts (detected, reached, skipped, pick attempts, picked by its judgement), the truth's (bolls
  /// present and picked, distance) and the paper's metrics. The run's time is the machine's own (its time_s), or at
  /// the time limit (or without it) the simulated time since the machine started.
  HarvestScore score(const StackFigures& stack, const RoverTruth& truth) const;

 private:
  std::vector<bool> reachable_;
  Eigen::Vector3d start_position_;
};

/// The one-line report of a run (node: the name in front).
std::string summaryLine(const std::string& node, const HarvestScore& score, const SimRunFigures& run);
/// A line per boll the vacuum did not take, for comparing runs boll by boll.
std::vector<std::string> missedBollLines(const std::string& node, const HarvestScore& score);

}  // namespace sim
}  // namespace cotton_harvester
