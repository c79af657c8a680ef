#include "cotton_harvester/sim/sim_harvest_plant.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "cotton_harvester/control/leaf_clearance.h"
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
      {"arm_timeout_s", arm_timeout_s},         {"pick_dwell_s", pick_dwell_s},
      {"arm_max_depth_m", arm_max_depth_m},     {"horizontal_travel_m", horizontal_travel_m}};
  for (const auto& [key, v] : values)
    if (!positive(v)) return std::string(key) + ": expected > 0";
  if (!(effector_prior_m > 0.0)) return "effector_prior_m: expected > 0";
  const std::pair<const char*, double> clearing[] = {{"leaf_clearance_m", leaf_clearance_m},
                                                     {"clear_overshoot_m", clear_overshoot_m},
                                                     {"clear_standoff_m", clear_standoff_m},
                                                     {"redetect_radius_m", redetect_radius_m}};
  for (const auto& [key, v] : clearing)
    if (!(v >= 0.0) || !std::isfinite(v)) return std::string(key) + ": expected >= 0";
  if (leaf_points_min < 1) return "leaf_points_min: expected >= 1";
  if (!(settle_s >= 0.0) || !(rover_timeout_per_m_s >= 0.0)) return "settle_s: expected >= 0";
  if (!(arm_min_depth_m >= 0.0 && arm_min_depth_m < arm_max_depth_m))
    return "arm_min_depth_m: expected 0 <= min < arm_max_depth_m";
  if (!(rest_extension_m >= 0.0 && rest_extension_m <= horizontal_travel_m))
    return "rest_extension_m: expected within [0, horizontal_travel_m]";
  if (!(rest_depth_m >= arm_min_depth_m && rest_depth_m <= arm_max_depth_m))
    return "rest_depth_m: expected within the vertical axis' depths";
  if (auto bad = canopy.check(); !bad.empty()) return "canopy/" + bad;
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
  s.arm_base_offset_m = sim.geometry.arm_base_offset_m;
  s.arm_min_depth_m = sim.geometry.min_depth_m;
  s.arm_max_depth_m = sim.geometry.max_depth_m;
  s.horizontal_travel_m = sim.geometry.horizontal_travel_m;
  s.effector_half_m = sim.geometry.effector_half_m;
  s.canopy.effector_half_m = sim.geometry.effector_half_m;
  s.canopy.housing_height_m = sim.geometry.effector_height_m;
  return s;
}

SimHarvestPlant::SimHarvestPlant(RoverSim& sim, const StackParams& params,
                                 std::unique_ptr<perception::PerceptionPipeline> pipeline)
    : sim_(sim), params_(params), pipeline_(std::move(pipeline)), rover_(params.rover) {
  if (auto bad = params_.check(); !bad.empty()) throw std::invalid_argument("harvest stack: " + bad);
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
  const control::Point3 expected{sim_.horizontalPosition() - params_.arm_base_offset_m, 0.0, sim_.verticalPosition()};
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

control::MoveResult SimHarvestPlant::moveRover(double distance_m, const Preempted& preempted) {
  if (!std::isfinite(distance_m)) return control::MoveResult::kFailed;
  // Drive with the arm up, clear of the plants: both axes go to their rest as the drive starts (the pump needs
  // most of a second to cross its deadband, and the arm's steppers are independent of it).
  sim_.commandHorizontal(params_.rest_extension_m);
  if (sim_.verticalPosition() > params_.rest_depth_m) sim_.commandVertical(params_.rest_depth_m);
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

control::MoveResult SimHarvestPlant::moveArmToDepth(double depth_m, const Preempted& preempted) {
  if (!std::isfinite(depth_m)) return control::MoveResult::kFailed;
  sim_.commandVertical(std::clamp(depth_m, params_.arm_min_depth_m, params_.arm_max_depth_m));
  if (!waitArm(preempted)) return preempted() ? control::MoveResult::kPreempted : control::MoveResult::kFailed;
  return control::MoveResult::kDone;
}

std::optional<perception::EndEffectorPrior> SimHarvestPlant::effectorPrior() const {
  if (!params_.effector_search_near_arm) return std::nullopt;
  perception::EndEffectorPrior p;
  p.position = cv::Point3d(sim_.horizontalPosition() - params_.arm_base_offset_m, 0.0, sim_.verticalPosition());
  p.radius_m = params_.effector_prior_m;
  p.housing_half_m = params_.effector_half_m;
  return p;
}

control::CloudView SimHarvestPlant::cloudView() const {
  control::CloudView view;
  if (cloud_.empty()) return view;
  view.data = cloud_.data;
  view.rows = cloud_.rows;
  view.cols = cloud_.cols;
  view.row_step = cloud_.step;
  view.point_step = cloud_.elemSize();
  return view;
}

perception::FrameResult SimHarvestPlant::newFrame() {
  run(params_.settle_s);
  sim_.renderCamera(&bgr_, &cloud_);
  perception::FrameResult result = pipeline_->process(bgr_, cloud_, effectorPrior());
  ++frames_;
  if (hook_) hook_(bgr_, result);
  return result;
}

int SimHarvestPlant::pointsOverApproach(double target_x, double depth_m) const {
  if (cloud_.empty()) return 0;
  const control::CloudView view = cloudView();
  control::LeafClearanceParams leaf;
  leaf.leaf_clearance_m = params_.leaf_clearance_m;
  leaf.effector_half_m = params_.effector_half_m;
  return control::pointsOverApproach(view, sim_.horizontalPosition() - params_.arm_base_offset_m, target_x, depth_m,
                                     leaf);
}

double SimHarvestPlant::clearAndRelocate(double target_x, const Preempted& preempted, bool* ok) {
  *ok = true;
  const double depth = sim_.verticalPosition();
  const double from = sim_.horizontalPosition();
  const double target_ext = target_x + params_.arm_base_offset_m;
  const double dir = target_ext >= from ? 1.0 : -1.0;
  const auto ext = [this](double e) { return std::clamp(e, 0.0, params_.horizontal_travel_m); };
  ++picks_cleared_;
  // Up to the leaf's level, through it past the boll, back off, down to the boll's top again.
  sim_.commandVertical(std::clamp(depth - params_.leaf_clearance_m, params_.arm_min_depth_m, params_.arm_max_depth_m));
  if (!(*ok = waitArm(preempted))) return target_x;
  sim_.commandHorizontal(ext(target_ext + dir * params_.clear_overshoot_m));
  if (!(*ok = waitArm(preempted))) return target_x;
  sim_.commandHorizontal(ext(target_ext - dir * params_.clear_standoff_m));
  if (!(*ok = waitArm(preempted))) return target_x;
  sim_.commandVertical(depth);
  if (!(*ok = waitArm(preempted))) return target_x;
  // Look again: the boll is now in full view, located on its whole top rather than on the part past the leaf.
  const perception::FrameResult result = newFrame();
  double best = params_.redetect_radius_m;
  double corrected = target_x, corrected_depth = depth;
  for (const auto& b : result.bolls) {
    const double d = std::hypot(b.position.x - target_x, b.position.y, b.position.z - depth);
    if (d < best) {
      best = d;
      corrected = b.position.x;
      corrected_depth = b.position.z;
    }
  }
  if (best < params_.redetect_radius_m) {
    ++picks_redetected_;
    // A boll seen only at its side past the leaf was located deeper than its top: the housing goes to the top.
    if (std::abs(corrected_depth - depth) > 0.015) {
      sim_.commandVertical(std::clamp(corrected_depth, params_.arm_min_depth_m, params_.arm_max_depth_m));
      *ok = waitArm(preempted);
    }
  }
  return corrected;
}

control::MoveResult SimHarvestPlant::pick(double offset_m, const Preempted& preempted) {
  if (!std::isfinite(offset_m)) return control::MoveResult::kFailed;
  const auto failed = [&] { return preempted() ? control::MoveResult::kPreempted : control::MoveResult::kFailed; };
  double target_x = sim_.horizontalPosition() - params_.arm_base_offset_m + offset_m;
  if (params_.clear_leaves_before_pick &&
      pointsOverApproach(target_x, sim_.verticalPosition()) >= params_.leaf_points_min) {
    bool ok = true;
    target_x = clearAndRelocate(target_x, preempted, &ok);
    if (!ok) return failed();
  }
  const double target = std::clamp(target_x + params_.arm_base_offset_m, 0.0, params_.horizontal_travel_m);
  sim_.commandHorizontal(target);
  if (!waitArm(preempted)) return failed();
  sim_.setVacuum(true);
  run(params_.pick_dwell_s);
  sim_.commandHorizontal(params_.rest_extension_m);
  const bool back = waitArm(preempted);
  sim_.setVacuum(false);
  if (params_.raise_after_pick) {
    sim_.commandVertical(params_.rest_depth_m);
    if (!waitArm(preempted)) return failed();
  }
  if (preempted()) return control::MoveResult::kPreempted;
  return back ? control::MoveResult::kDone : control::MoveResult::kFailed;
}

std::optional<control::MoveResult> SimHarvestPlant::searchUnderLeaves(const Preempted& preempted) {
  const control::CanopySearchParams& c = params_.canopy;
  const auto failed = [&] { return preempted() ? control::MoveResult::kPreempted : control::MoveResult::kFailed; };
  // The housing above the plants at its rest, then a frame: everything deeper than the housing is the canopy.
  sim_.commandHorizontal(params_.rest_extension_m);
  if (sim_.verticalPosition() > params_.rest_depth_m) sim_.commandVertical(params_.rest_depth_m);
  if (!waitArm(preempted)) return failed();
  newFrame();
  ++leaf_searches_;
  const double fx = pipeline_->params().intrinsics.fx;
  control::ArmWorkspace arm;
  arm.extension_zero_x_m = -params_.arm_base_offset_m;
  arm.extension_max_m = params_.horizontal_travel_m;
  arm.rest_depth_m = params_.rest_depth_m;
  arm.max_depth_m = params_.arm_max_depth_m;
  arm.strip_y_m = 0.0;  // the calibration's arm plane
  control::CanopySearch search(arm, c);
  int passes = 0;
  for (int pass = 0; pass < c.max_passes; ++pass) {
    const auto sweep = search.next(cloudView(), fx);
    if (!sweep) break;
    // Beside the layer above the plants, down (no leaf is pushed by a vertical move), through it, up again.
    sim_.commandHorizontal(sweep->from_extension_m);
    if (!waitArm(preempted)) return failed();
    sim_.commandVertical(sweep->depth_m);
    if (!waitArm(preempted)) return failed();
    sim_.commandHorizontal(sweep->to_extension_m);
    if (!waitArm(preempted)) return failed();
    sim_.commandVertical(params_.rest_depth_m);
    if (!waitArm(preempted)) return failed();
    ++passes;
    ++leaf_sweeps_;
    if (pass + 1 < c.max_passes) newFrame();
  }
  sim_.commandHorizontal(params_.rest_extension_m);
  if (!waitArm(preempted)) return failed();
  if (passes == 0) return std::nullopt;
  return control::MoveResult::kDone;
}

}  // namespace sim
}  // namespace cotton_harvester
