#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "cotton_harvester/control/harvest_actions.h"
#include "cotton_harvester/control/deadband_position_controller.h"
#include "cotton_harvester/perception/colour_boll_detector.h"
#include "cotton_harvester/perception/perception_pipeline.h"
#include "cotton_harvester_sim/rover_sim.h"

namespace cotton_harvester {
namespace sim {

/// How the harvest stack's plant talks to the simulated rover: the rover's position control, when a move or a frame
/// is done, and where perception looks for the end-effector. How the arm picks, clears leaves and rests is not here
/// (control::HarvestActionParams, shared with the robot's node).
struct StackParams {
  control::DeadbandControllerParams rover;  ///< position control of the hydrostatic drive on the encoder
  double control_period_s = 0.02;           ///< the navigation controller's telemetry rate (50 Hz)
  double metres_per_pulse = 0.0018;         ///< encoder (§2.11)
  double rover_tolerance_m = 0.02;          ///< a move is done within this of its target, at rest
  double rover_settle_s = 0.2;              ///< ... and the encoder still for this long [s]
  double rover_timeout_s = 20.0;            ///< + rover_timeout_per_m_s per metre: the move failed
  double rover_timeout_per_m_s = 20.0;
  double arm_timeout_s = 15.0;
  double settle_s = 0.15;         ///< wait after an action before the frame is taken
  double effector_half_m = 0.05;  ///< the end-effector housing's half side, for perception's search of it
  /// The end-effector perception finds is taken only within this of where the arm's calibration (stepper counters)
  /// puts it [m]; otherwise (another orange-like region, or the housing hidden) ...
  double effector_prior_m = 0.08;
  /// ... the calibrated position stands in for it (false: the frame has no end-effector).
  bool effector_from_calibration = true;
  /// Perception searches for the housing only within effector_prior_m of where the calibration puts it and takes
  /// the orange region there that agrees with it in 3D (false: the largest orange region of the whole image).
  bool effector_search_near_arm = true;
  std::string check() const;  ///< empty when sound
};

/// The harvest stack's side of the simulated rover: the HarvestPlant primitives the state machine's manoeuvres
/// (control::HarvestActions) drive. It sees only what the real rover's stack sees — camera frames through the
/// perception pipeline, the wheel encoder, the stepper counters — and commands the swashplate PWM (through the
/// deadband-aware position controller), the steppers and the vacuum. Time passes by stepping the simulator, so
/// actions block in simulated time.
class SimHarvestPlant : public control::HarvestPlant {
 public:
  /// Called after every camera frame with the image and what perception made of it (for debug output).
  using FrameHook = std::function<void(const cv::Mat& bgr, const perception::FrameResult& result)>;

  /// `arm`: the arm's calibration as the stack knows it (HarvestActionParams::arm). Throws std::invalid_argument on
  /// bad parameters.
  SimHarvestPlant(RoverSim& sim, const StackParams& params, const control::ArmWorkspace& arm,
                  std::unique_ptr<perception::PerceptionPipeline> pipeline);

  std::optional<control::HarvestObservation> observe(const Preempted& preempted) override;
  control::MoveResult moveRover(double distance_m, const control::ArmPose& arm, const Preempted& preempted) override;
  control::MoveResult moveArm(const control::ArmPose& target, const Preempted& preempted) override;
  std::optional<control::ArmPose> armPose() const override;
  void setVacuum(bool on) override { sim_.setVacuum(on); }
  control::MoveResult wait(double seconds, const Preempted& preempted) override;
  std::optional<control::CameraCloud> lastCloud(const Preempted& preempted) override;
  double now() const override { return sim_.time(); }
  double roverPositionM() const override;

  void setFrameHook(FrameHook hook) { hook_ = std::move(hook); }
  int frames() const { return frames_; }
  int framesWithEffector() const { return frames_with_effector_; }
  /// Frames whose end-effector was too far from the calibrated position, and frames that used the calibration.
  int effectorRejected() const { return effector_rejected_; }
  int effectorFromCalibration() const { return effector_from_calibration_; }
  /// Rover position samples (time [s], encoder position [m]) at the control rate, for plots.
  const std::vector<std::pair<double, double>>& track() const { return track_; }

 private:
  /// Steps the simulator for `seconds` with the rover's position controller closing its loop every period.
  void run(double seconds);
  bool waitArm(const Preempted& preempted);
  /// Commands the pose's finite axes (the simulated axes clamp to their travel).
  void commandArm(const control::ArmPose& pose);
  /// The frame's end-effector prior from the stepper counters (nullopt when the search is not restricted).
  std::optional<perception::EndEffectorPrior> effectorPrior() const;

  RoverSim& sim_;
  StackParams params_;
  control::ArmWorkspace arm_;
  std::unique_ptr<perception::PerceptionPipeline> pipeline_;
  control::DeadbandPositionController rover_;
  double target_m_ = 0.0;
  FrameHook hook_;
  int frames_ = 0, frames_with_effector_ = 0, effector_rejected_ = 0, effector_from_calibration_ = 0;
  std::vector<std::pair<double, double>> track_;
  cv::Mat bgr_, cloud_;
};

/// The perception settings for the simulated camera: the paper's pipeline with the rover's arm geometry.
perception::PerceptionParams simPerceptionParams(const RoverSimParams& sim);
/// The colour detector's settings for the simulated rover: the defaults, and partial bolls reported.
perception::ColourBollParams simColourBollParams();
/// The stack settings that match the simulated rover's build (what a user calibrates on the real one).
StackParams simStackParams(const RoverSimParams& sim);
/// The harvest manoeuvres' settings for the simulated rover's arm (its calibration, travel and housing); the rest
/// are the defaults the robot's node has.
control::HarvestActionParams simActionParams(const RoverSimParams& sim);

}  // namespace sim
}  // namespace cotton_harvester
