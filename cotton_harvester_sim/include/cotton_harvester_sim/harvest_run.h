#pragma once

#include <functional>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "cotton_harvester/control/harvest_machine.h"
#include "cotton_harvester/control/harvest_metrics.h"
#include "cotton_harvester_sim/miss_causes.h"
#include "cotton_harvester_sim/sim_harvest_plant.h"

namespace cotton_harvester {
namespace sim {

/// One harvest of a simulated row: the simulator, the stack and the state machine's settings.
struct HarvestRunConfig {
  RoverSimParams sim;
  /// row_length_m is how far the rover drives; actions: the arm's manoeuvres, as the robot's node has them
  control::HarvestParams machine;
  double time_limit_s = 900.0;   ///< simulated time after which the run is stopped (preempted)
  std::string debug_image_path;  ///< when set: a PNG of the first frame with a boll and the end-effector found
  std::string frames_dir;        ///< when set: every camera frame with its detections as PNG (frame_NNNN.png)
  /// Called with the machine's status on every change (e.g. to publish it).
  std::function<void(const thorvald_state_machine::StatusSnapshot&)> status_observer;
  bool verbose = false;  ///< print every transition of the machine (simulated time, state, outcome)
  /// StackParams::effector_search_near_arm of the stack on the rover (how the arm picks: machine.actions).
  bool effector_search_near_arm = true;
  bool partial_bolls = true;  ///< the colour detector reports partial bolls (simColourBollParams)
};

/// What came out of a run. `counts.picked` and the metrics are the simulation's (bolls the vacuum really took);
/// `machine_picked` is what the state machine believed.
struct HarvestRunReport {
  std::string outcome;  ///< the machine's: finished, aborted, preempted
  control::HarvestCounts counts;
  control::HarvestMetrics metrics;
  int machine_picked = 0;
  int bolls_present = 0;
  int bolls_reachable = 0;  ///< truth: bolls inside the arm's workspace along the driven stretch
  int frames = 0, frames_with_effector = 0;
  int effector_rejected = 0, effector_from_calibration = 0;
  int picks_cleared = 0, picks_redetected = 0;  ///< picks that swept leaves first; of them, corrected by a new frame
  int leaves_pushed = 0;                        ///< leaves the housing pushed away from where they grew
  int bolls_knocked_off = 0;                    ///< datasheet: bolls the housing broke off their branch
  int leaf_searches = 0, leaf_sweeps = 0;       ///< places the arm looked under the leaves; its sweeps there
  double sim_time_s = 0.0, wall_time_s = 0.0;
  std::set<std::string> states_visited;
  std::vector<std::pair<double, double>> rover_track;  ///< (time [s], encoder position [m])
  std::vector<BollTruth> bolls;                        ///< truth at the end: positions, captured or not
  Eigen::Vector3d rover_start = Eigen::Vector3d::Zero(), rover_end = Eigen::Vector3d::Zero();
  /// The encoder's travel minus the true travel along the row at the end [m] (wheel slip): the tracker's row
  /// coordinates, and so a boll aimed at from memory, are off by about this much late in a run.
  double odometry_error_m = 0.0;
  int divergences = 0;
  /// Per boll (the order of `bolls`): what the scorer saw of it, and why it was missed (kCaptured when taken).
  std::vector<BollRecord> boll_records;
  std::vector<MissCause> miss_causes;
  MissTable misses;
  /// Simulated time spent in each state of the machine [s] and how often it was entered.
  std::map<std::string, double> state_time_s;
  std::map<std::string, int> state_entries;
  /// Perception against the truth, per frame: each matched detection's position minus its boll's true top, signed
  /// depth (z) and 3D distance [m]; the end-effector's measured depth minus its housing's true top face [m].
  std::vector<double> boll_depth_errors_m, boll_errors_m, effector_depth_errors_m;
  std::string error;  ///< set when the run could not be done (model, renderer)
};

/// Simulated time spent in each state of the machine and how often each was entered, from its active state as it
/// changes (HarvestRunReport::states_visited, state_time_s, state_entries).
class StateTimeTally {
 public:
  explicit StateTimeTally(HarvestRunReport* report) : report_(report) {}
  /// The machine's active state at `now_s` (empty: none, e.g. before it starts or after it ends).
  void observe(const std::string& active_state, double now_s);
  /// Counts the time of the state still active at the end of the run.
  void finish(double now_s);

 private:
  HarvestRunReport* report_;
  std::string state_now_;
  double state_since_s_ = 0.0;
};

/// Builds the world and the rover, runs the harvest state machine on SimHarvestPlant until it ends (or the time
/// limit), and scores it against the simulation's truth. Never throws; `error` says what went wrong.
HarvestRunReport runHarvest(const HarvestRunConfig& config);

/// Bolls the arm can reach from the row's line as the rover drives `row_length_m` from where it stands now: the
/// boll's centre across the row within the end-effector's travel, its top no deeper than the vertical axis goes, and
/// passed by the camera's optical axis during the drive. From the truth, for scoring only (one flag per sim.bolls()).
std::vector<bool> reachableBolls(const RoverSim& sim, double row_length_m);

/// The paper's two experiments (§2.13): potted defoliated plants (Table 2) and a field-like undefoliated row
/// (Table 3). `seed` varies the plants.
HarvestRunConfig pottedConfig(unsigned seed);
HarvestRunConfig fieldConfig(unsigned seed);

/// Writes the camera's frame of the rover over the row of `base` in ideal and in datasheet side by side (colour
/// above, depth below) as PNG. False when it cannot be written.
bool writeRealismFrames(const RoverSimParams& base, const std::string& path);

/// Writes a top view of the run (rover path along the row, picked bolls green, missed red) as PNG.
bool writePathPng(const HarvestRunReport& report, const std::string& path);

}  // namespace sim
}  // namespace cotton_harvester
