#include "cotton_harvester_sim/sim_harvest_plant.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "cotton_harvester/perception/colour_boll_detector.h"

namespace cotton_harvester {
namespace sim {

namespace {
bool positive(double v) { return v > 0.0 && std::isfinite(v); }
}  // namespace

std::string StackParams::check() const {
  if (auto bad = rover.check(); !bad.empty()) return "rover/" + bad;
  const std::pair<const char*, double> values[] = {
      {"control_period_s", control_period_s},   {"metres_per_pulse", metres_per_pulse},
      {"rover_tolerance_m", rover_tolerance_m}, {"rover_timeout_s", rover_timeout_s},
      {"arm_timeout_s", arm_timeout_s},         {"effector_half_m", effector_half_m}};
  for (const auto& [key, v] : values)
    if (!positive(v)) return std::string(key) + ": expected > 0";
  if (!(effector_prior_m > 0.0)) return "effector_prior_m: expected > 0";
  if (!(settle_s >= 0.0) || !(rover_timeout_per_m_s >= 0.0)) return "settle_s: expected >= 0";
  return "";
}

perception::PerceptionParams simPerceptionParams(const RoverSimParams& sim) {
  perception::PerceptionParams p;
  p.intrinsics.fx = p.intrinsics.fy = sim.fx;
  p.intrinsics.cx = sim.cx;
  p.intrinsics.cy = sim.cy;
  p.intrinsics.width = sim.camera_width;
  p.intrinsics.height = sim.camera_height;
  p.geometry.camera_height_m = sim.geometry.camera_height_m;
  p.end_effector.arm_direction = cv::Point2d(-1.0, 0.0);
  p.end_effector.arm_base_offset_m = sim.geometry.arm_base_offset_m;
  p.reach.max_depth_m = sim.geometry.max_depth_m;
  p.reach.arm_origin_x_m = -sim.geometry.arm_base_offset_m + 0.5 * sim.geometry.horizontal_travel_m;
  p.reach.horizontal_arm_length_m = 0.5 * sim.geometry.horizontal_travel_m + sim.geometry.effector_half_m;
  return p;
}

perception::ColourBollParams simColourBollParams() {
  perception::ColourBollParams c;
  // The picker pushes leaves aside and looks again (StackParams::clear_leaves_before_pick), so a boll seen only
  // partly past a leaf is worth approaching: regions of at least 0.6 of the smallest boll's disc that fail the
  // whole-boll shape tests are reported as partial bolls.
  c.partial_min_fraction = 0.6;
  return c;
}

StackParams simStackParams(const RoverSimParams& sim) {
  StackParams s;
  s.metres_per_pulse = sim.drive.metres_per_pulse;
  s.effector_half_m = sim.geometry.effector_half_m;
  return s;
}

control::HarvestActionParams simActionParams(const RoverSimParams& sim) {
  const RoverGeometry& g = sim.geometry;
  control::HarvestActionParams a;
  a.arm.extension_zero_x_m = -g.arm_base_offset_m;
  a.arm.extension_min_m = 0.0;
  a.arm.extension_max_m = g.horizontal_travel_m;
  a.arm.min_depth_m = g.min_depth_m;
  a.arm.max_depth_m = g.max_depth_m;
  a.arm.strip_y_m = 0.0;  // the arm's plane is the camera's y = 0
  a.leaves.effector_half_m = g.effector_half_m;
  a.canopy.effector_half_m = g.effector_half_m;
  a.canopy.housing_height_m = g.effector_height_m;
  return a;
}

SimHarvestPlant::SimHarvestPlant(RoverSim& sim, const StackParams& params, const control::ArmWorkspace& arm,
                                 std::unique_ptr<perception::PerceptionPipeline> pipeline)
    : sim_(sim), params_(params), arm_(arm), pipeline_(std::move(pipeline)), rover_(params.rover) {
  if (auto bad = params_.check(); !bad.empty()) throw std::invalid_argument("harvest stack: " + bad);
  if (!std::isfinite(arm_.extension_zero_x_m) || !std::isfinite(arm_.strip_y_m))
    throw std::invalid_argument("harvest stack: arm_extension_zero_x_m, arm_y_m: expected finite numbers");
  if (!pipeline_) throw std::invalid_argument("harvest stack: no perception pipeline");
  target_m_ = roverPositionM();
  rover_.setTarget(target_m_);
}

double SimHarvestPlant::roverPositionM() const { return sim_.encoderCount() * params_.metres_per_pulse; }

void SimHarvestPlant::run(double seconds) {
  const int periods = std::max(1, static_cast<int>(std::lround(seconds / params_.control_period_s)));
  for (int i = 0; i < periods; ++i) {
    const double position = roverPositionM();
    sim_.setSwashplatePwm(rover_.update(position, params_.control_period_s));
    sim_.advance(params_.control_period_s);
    track_.emplace_back(sim_.time(), position);
  }
}

std::optional<control::HarvestObservation> SimHarvestPlant::observe(const Preempted& preempted) {
  if (preempted()) return std::nullopt;
  run(params_.settle_s);
  control::HarvestObservation obs;
  obs.stamp_s = sim_.time();
  obs.rover_position_m = roverPositionM();
  // Where the arm's calibration puts the housing's top face, from the stepper counters.
  const control::Point3 expected{sim_.horizontalPosition() + arm_.extension_zero_x_m, arm_.strip_y_m,
                                 sim_.verticalPosition()};
  sim_.renderCamera(&bgr_, &cloud_);
  const perception::FrameResult result = pipeline_->process(bgr_, cloud_, effectorPrior());
  ++frames_;
  if (hook_) hook_(bgr_, result);
  if (result.status != perception::FrameStatus::kOk) return std::nullopt;
  for (const auto& b : result.bolls) {
    control::BollSighting s;
    s.position = {b.position.x, b.position.y, b.position.z};
    s.confidence = b.detection.confidence;
    s.reachable = b.reachable;
    obs.bolls.push_back(s);
  }
  if (result.end_effector) {
    const cv::Point3d& p = result.end_effector->position;
    const double off = std::hypot(p.x - expected.x, p.y - expected.y, p.z - expected.z);
    if (off <= params_.effector_prior_m) {
      ++frames_with_effector_;
      obs.end_effector = control::Point3{p.x, p.y, p.z};
      return obs;
    }
    ++effector_rejected_;  // an orange-like region elsewhere (a terracotta pot) was taken for the housing
  } else if (result.end_effector_candidates_refused > 0) {
    ++effector_rejected_;  // orange regions where the arm can be, none of them the housing
  }
  if (params_.effector_from_calibration) {
    ++effector_from_calibration_;
    obs.end_effector = expected;
  }
  return obs;
}

void SimHarvestPlant::commandArm(const control::ArmPose& pose) {
  sim_.commandHorizontal(pose.extension_m);  // NaN: the axis keeps its target
  sim_.commandVertical(pose.depth_m);
}

control::MoveResult SimHarvestPlant::moveRover(double distance_m, const control::ArmPose& arm,
                                               const Preempted& preempted) {
  if (!std::isfinite(distance_m)) return control::MoveResult::kFailed;
  // The arm's steppers are independent of the drive: they move while the pump crosses its deadband.
  commandArm(arm);
  target_m_ = roverPositionM() + distance_m;
  rover_.setTarget(target_m_);
  const double timeout = params_.rover_timeout_s + params_.rover_timeout_per_m_s * std::abs(distance_m);
  const double start = sim_.time();
  // Done when the controller holds neutral and the encoder has not moved for rover_settle_s (the controller goes
  // to neutral early and lets the rover coast to the target; it restarts by itself if the rover stops short).
  double still_s = 0.0;
  std::int32_t last_count = sim_.encoderCount();
  while (still_s < params_.rover_settle_s) {
    if (preempted()) return control::MoveResult::kPreempted;
    if (sim_.time() - start > timeout) return control::MoveResult::kFailed;
    run(params_.control_period_s);
    const std::int32_t count = sim_.encoderCount();
    still_s = rover_.atRest() && count == last_count && !sim_.armMoving() ? still_s + params_.control_period_s : 0.0;
    last_count = count;
  }
  return std::abs(roverPositionM() - target_m_) <=
                 std::max(params_.rover_tolerance_m, params_.rover.restart_tolerance_m)
             ? control::MoveResult::kDone
             : control::MoveResult::kFailed;
}

bool SimHarvestPlant::waitArm(const Preempted& preempted) {
  const double start = sim_.time();
  while (sim_.armMoving()) {
    if (preempted() || sim_.time() - start > params_.arm_timeout_s) return false;
    run(params_.control_period_s);
  }
  return true;
}

control::MoveResult SimHarvestPlant::moveArm(const control::ArmPose& target, const Preempted& preempted) {
  commandArm(target);
  if (!waitArm(preempted)) return preempted() ? control::MoveResult::kPreempted : control::MoveResult::kFailed;
  return control::MoveResult::kDone;
}

std::optional<control::ArmPose> SimHarvestPlant::armPose() const {
  return control::ArmPose{sim_.horizontalPosition(), sim_.verticalPosition()};
}

control::MoveResult SimHarvestPlant::wait(double seconds, const Preempted& preempted) {
  run(seconds);
  return preempted() ? control::MoveResult::kPreempted : control::MoveResult::kDone;
}

std::optional<control::CameraCloud> SimHarvestPlant::lastCloud(const Preempted&) {
  if (cloud_.empty()) return std::nullopt;
  control::CameraCloud c;
  c.view.data = cloud_.data;
  c.view.rows = cloud_.rows;
  c.view.cols = cloud_.cols;
  c.view.row_step = cloud_.step;
  c.view.point_step = cloud_.elemSize();
  c.fx_px = pipeline_->params().intrinsics.fx;
  c.keep = std::make_shared<cv::Mat>(cloud_);  // holds the pixels; the next frame may render over them
  return c;
}

std::optional<perception::EndEffectorPrior> SimHarvestPlant::effectorPrior() const {
  if (!params_.effector_search_near_arm) return std::nullopt;
  perception::EndEffectorPrior p;
  p.position =
      cv::Point3d(sim_.horizontalPosition() + arm_.extension_zero_x_m, arm_.strip_y_m, sim_.verticalPosition());
  p.radius_m = params_.effector_prior_m;
  p.housing_half_m = params_.effector_half_m;
  return p;
}

}  // namespace sim
}  // namespace cotton_harvester
