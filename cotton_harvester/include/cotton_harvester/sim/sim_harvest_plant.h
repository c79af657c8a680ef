#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "cotton_harvester/control/canopy_search.h"
#include "cotton_harvester/control/deadband_position_controller.h"
#include "cotton_harvester/control/harvest_machine.h"
#include "cotton_harvester/perception/colour_boll_detector.h"
#include "cotton_harvester/perception/perception_pipeline.h"
#include "cotton_harvester/sim/rover_sim.h"

namespace cotton_harvester {
namespace sim {

/// How the harvest stack runs its actions on the rover.
struct StackParams {
  control::DeadbandControllerParams rover;  ///< position control of the hydrostatic drive on the encoder
  double control_period_s = 0.02;           ///< the navigation controller's telemetry rate (50 Hz)
  double metres_per_pulse = 0.0018;         ///< encoder (§2.11)
  double rover_tolerance_m = 0.02;          ///< a move is done within this of its target, at rest
  double rover_settle_s = 0.2;              ///< ... and the encoder still for this long [s]
  double rover_timeout_s = 20.0;            ///< + rover_timeout_per_m_s per metre: the move failed
  double rover_timeout_per_m_s = 20.0;
  double arm_timeout_s = 15.0;
  double settle_s = 0.15;          ///< wait after an action before the frame is taken
  double pick_dwell_s = 1.0;       ///< vacuum on at the boll [s]
  double rest_extension_m = 0.35;  ///< horizontal axis between picks
  double rest_depth_m = 1.20;      ///< end-effector depth while driving on (above the plants)
  /// After a pick the arm goes up to rest_depth_m at once (true), or stays at the boll's depth for the next boll of
  /// the same stop and goes up only when the rover moves (false).
  bool raise_after_pick = false;
  double arm_base_offset_m = 0.55;  ///< the calibration the stack knows: horizontal extension 0 = camera x
  double arm_min_depth_m = 0.30;    ///< -arm_base_offset_m; depth limits of the vertical axis
  double arm_max_depth_m = 1.93;
  double horizontal_travel_m = 0.70;
  double effector_half_m = 0.05;  ///< the extension is of the end-effector's centre
  /// The end-effector perception finds is taken only within this of where the arm's calibration (stepper counters)
  /// puts it [m]; otherwise (another orange-like region, or the housing hidden) ...
  double effector_prior_m = 0.08;
  /// ... the calibrated position stands in for it (false: the frame has no end-effector).
  bool effector_from_calibration = true;
  /// Perception searches for the housing only within effector_prior_m of where the calibration puts it and takes
  /// the orange region there that agrees with it in 3D (false: the largest orange region of the whole image).
  bool effector_search_near_arm = true;
  /// Before a pick, when the last frame's cloud shows something above the boll along the arm's approach (a leaf
  /// over it: at least leaf_points_min points between leaf_clearance_m above the boll's top and its top, within the
  /// housing's width of the approach line), the arm first sweeps through it leaf_clearance_m higher, overshooting
  /// the boll by clear_overshoot_m, so the leaf is pushed aside, and backs off to clear_standoff_m short of it.
  bool clear_leaves_before_pick = true;
  double leaf_clearance_m = 0.06;
  double clear_overshoot_m = 0.04;
  double clear_standoff_m = 0.12;
  int leaf_points_min = 40;
  /// After clearing, a new frame: the boll located nearest the target within redetect_radius_m sets the pick's
  /// final position (a boll seen only partly past a leaf is located a few centimetres off).
  double redetect_radius_m = 0.07;
  /// How the arm looks under the leaves when the machine asks (HarvestParams::search_under_leaves): the strip, the
  /// layers, the sweeps. The housing's size comes from effector_half_m and the vertical axis' limits.
  control::CanopySearchParams canopy;
  std::string check() const;  ///< empty when sound
};

/// The harvest stack's side of the simulated rover: the HarvestPlant the state machine drives. It sees only what
/// the real rover's stack sees — camera frames through the perception pipeline, the wheel encoder, the stepper
/// counters — and commands the swashplate PWM (through the deadband-aware position controller), the steppers and
/// the vacuum. Time passes by stepping the simulator, so actions block in simulated time.
class SimHarvestPlant : public control::HarvestPlant {
 public:
  /// Called after every camera frame with the image and what perception made of it (for debug output).
  using FrameHook = std::function<void(const cv::Mat& bgr, const perception::FrameResult& result)>;

  /// Throws std::invalid_argument on bad parameters.
  SimHarvestPlant(RoverSim& sim, const StackParams& params, std::unique_ptr<perception::PerceptionPipeline> pipeline);

  std::optional<control::HarvestObservation> observe(const Preempted& preempted) override;
  control::MoveResult moveRover(double distance_m, const Preempted& preempted) override;
  control::MoveResult moveArmToDepth(double depth_m, const Preempted& preempted) override;
  control::MoveResult pick(double offset_m, const Preempted& preempted) override;
  std::optional<control::MoveResult> searchUnderLeaves(const Preempted& preempted) override;
  double now() const override { return sim_.time(); }
  double roverPositionM() const override;

  void setFrameHook(FrameHook hook) { hook_ = std::move(hook); }
  int frames() const { return frames_; }
  int framesWithEffector() const { return frames_with_effector_; }
  /// Frames whose end-effector was too far from the calibrated position, and frames that used the calibration.
  int effectorRejected() const { return effector_rejected_; }
  int effectorFromCalibration() const { return effector_from_calibration_; }
  /// Picks that swept leaves aside first, and of them those whose target a new frame corrected.
  int picksCleared() const { return picks_cleared_; }
  int picksRedetected() const { return picks_redetected_; }
  /// Places of the row where the arm looked under the leaves, and its sweeps through them.
  int leafSearches() const { return leaf_searches_; }
  int leafSweeps() const { return leaf_sweeps_; }
  /// Rover position samples (time [s], encoder position [m]) at the control rate, for plots.
  const std::vector<std::pair<double, double>>& track() const { return track_; }

 private:
  /// Steps the simulator for `seconds` with the rover's position controller closing its loop every period.
  void run(double seconds);
  bool waitArm(const Preempted& preempted);
  /// Cloud points of the last frame above the boll at (target_x, depth) along the approach from the housing.
  int pointsOverApproach(double target_x, double depth_m) const;
  /// Sweeps the leaves over the target aside and returns the target's x from a new frame (or target_x).
  double clearAndRelocate(double target_x, const Preempted& preempted, bool* ok);
  /// Renders a frame and runs perception on it (the frame hook sees it); the cloud stays in cloud_.
  perception::FrameResult newFrame();
  control::CloudView cloudView() const;
  /// The frame's end-effector prior from the stepper counters (nullopt when the search is not restricted).
  std::optional<perception::EndEffectorPrior> effectorPrior() const;

  RoverSim& sim_;
  StackParams params_;
  std::unique_ptr<perception::PerceptionPipeline> pipeline_;
  control::DeadbandPositionController rover_;
  double target_m_ = 0.0;
  FrameHook hook_;
  int frames_ = 0, frames_with_effector_ = 0, effector_rejected_ = 0, effector_from_calibration_ = 0;
  int picks_cleared_ = 0, picks_redetected_ = 0, leaf_searches_ = 0, leaf_sweeps_ = 0;
  std::vector<std::pair<double, double>> track_;
  cv::Mat bgr_, cloud_;
};

/// The perception settings for the simulated camera: the paper's pipeline with the rover's arm geometry.
perception::PerceptionParams simPerceptionParams(const RoverSimParams& sim);
/// The colour detector's settings for the simulated rover: the defaults, and partial bolls reported.
perception::ColourBollParams simColourBollParams();
/// The stack settings that match the simulated rover's build (what a user calibrates on the real one).
StackParams simStackParams(const RoverSimParams& sim);

}  // namespace sim
}  // namespace cotton_harvester
