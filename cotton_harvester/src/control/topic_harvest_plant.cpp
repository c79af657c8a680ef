#include "topic_harvest_plant.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cotton_harvester {
namespace control {

TopicHarvestPlant::TopicHarvestPlant(ros::NodeHandle& nh, const TopicPlantParams& params) : params_(params) {
  rover_target_pub_ = nh.advertise<std_msgs::Float64>("rover/position_target", 1, true);
  arm_target_pub_ = nh.advertise<geometry_msgs::PointStamped>("manipulator/target", 1, true);
  brush_pub_ = nh.advertise<std_msgs::Bool>("manipulator/brush", 1, true);
  bolls_sub_ = nh.subscribe("bolls", 2, &TopicHarvestPlant::onBolls, this);
  effector_sub_ = nh.subscribe("end_effector/position", 5, &TopicHarvestPlant::onEffector, this);
  rover_sub_ = nh.subscribe("rover/position", 5, &TopicHarvestPlant::onRoverPosition, this);
  joints_sub_ = nh.subscribe("manipulator/joint_states", 5, &TopicHarvestPlant::onJoints, this);
  busy_sub_ = nh.subscribe("manipulator/busy", 5, &TopicHarvestPlant::onBusy, this);
  if (params_.clear_leaves_before_pick || params_.search_under_leaves)
    cloud_sub_ = nh.subscribe("camera/depth/points", 2, &TopicHarvestPlant::onCloud, this);
}

void TopicHarvestPlant::onCloud(const sensor_msgs::PointCloud2::ConstPtr& msg) {
  std::lock_guard<std::mutex> lock(mutex_);
  clouds_.push_back(msg);
  while (clouds_.size() > 8) clouds_.pop_front();  // 2 s at 4 Hz: bolls can come late under load
  changed_.notify_all();
}

bool TopicHarvestPlant::observedCloud(sensor_msgs::PointCloud2::ConstPtr* keep, CloudView* out) const {
  sensor_msgs::PointCloud2::ConstPtr cloud;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& c : clouds_)
      if (c->header.stamp == last_used_stamp_) cloud = c;
  }
  if (!cloud || cloud->height < 2) return false;
  CloudView view;
  int found = 0;
  for (const auto& f : cloud->fields) {
    if (f.datatype != sensor_msgs::PointField::FLOAT32) continue;
    if (f.name == "x") view.x_offset = f.offset, found |= 1;
    if (f.name == "y") view.y_offset = f.offset, found |= 2;
    if (f.name == "z") view.z_offset = f.offset, found |= 4;
  }
  const std::size_t need = static_cast<std::size_t>(cloud->row_step) * cloud->height;
  if (found != 7 || cloud->is_bigendian || cloud->data.size() < need || cloud->point_step < 12 ||
      cloud->row_step < cloud->width * cloud->point_step)
    return false;
  view.data = cloud->data.data();
  view.rows = static_cast<int>(cloud->height);
  view.cols = static_cast<int>(cloud->width);
  view.row_step = cloud->row_step;
  view.point_step = cloud->point_step;
  *keep = cloud;
  *out = view;
  return true;
}

int TopicHarvestPlant::pointsOverApproach(double from_x, double target_x, double depth_m) const {
  sensor_msgs::PointCloud2::ConstPtr cloud;
  CloudView view;
  if (!observedCloud(&cloud, &view)) return 0;
  return control::pointsOverApproach(view, from_x, target_x, depth_m, params_.leaves);
}

std::optional<MoveResult> TopicHarvestPlant::searchUnderLeaves(const Preempted& preempted) {
  if (!params_.search_under_leaves || !(params_.rest_depth_m > 0.0)) return std::nullopt;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const CanopySearchParams& c = params_.canopy;
  // The housing above the plants, then a frame: everything deeper than the housing is the canopy.
  MoveResult result = moveArm(nan, params_.rest_depth_m, preempted);
  if (result != MoveResult::kDone) return result;
  if (!observe(preempted)) return preempted() ? MoveResult::kPreempted : MoveResult::kFailed;
  ++leaf_searches_;
  ArmWorkspace arm;
  arm.extension_zero_x_m = params_.arm_extension_zero_x_m;
  arm.extension_min_m = params_.horizontal_min_m;
  arm.extension_max_m = params_.horizontal_max_m;
  arm.rest_depth_m = params_.rest_depth_m;
  arm.max_depth_m = params_.vertical_max_m;
  arm.strip_y_m = params_.arm_y_m;
  CanopySearch search(arm, c);
  int passes = 0;
  for (int pass = 0; pass < c.max_passes; ++pass) {
    // The frame's cloud may come a little after its bolls (11 MB at 1280 x 720).
    bool was_preempted = false;
    waitFor(
        [this] {
          return std::any_of(clouds_.begin(), clouds_.end(),
                             [this](const auto& c) { return c->header.stamp == last_used_stamp_; });
        },
        params_.observe_timeout_s, preempted, &was_preempted);
    if (was_preempted) return MoveResult::kPreempted;
    sensor_msgs::PointCloud2::ConstPtr cloud;
    CloudView view;
    if (!observedCloud(&cloud, &view)) {
      ROS_WARN_THROTTLE(10.0,
                        "harvest plant: no cloud of the observed frame on camera/depth/points: cannot look "
                        "under the leaves");
      break;
    }
    const double fx = focalFromCloud(view);
    if (!(fx > 0.0)) break;
    const auto sweep = search.next(view, fx);
    if (!sweep) break;
    // Beside the layer above the plants, down (a vertical move pushes no leaf), through it, up again.
    const std::pair<double, double> moves[] = {{sweep->from_extension_m, nan},
                                               {nan, sweep->depth_m},
                                               {sweep->to_extension_m, nan},
                                               {nan, params_.rest_depth_m}};
    for (const auto& [x, z] : moves)
      if ((result = moveArm(x, z, preempted)) != MoveResult::kDone) return result;
    ++passes;
    ++leaf_sweeps_;
    if (pass + 1 < c.max_passes && !observe(preempted)) break;
  }
  if (passes == 0) return std::nullopt;
  return MoveResult::kDone;
}

double TopicHarvestPlant::clearAndRelocate(double target_ext, const Preempted& preempted, MoveResult* result) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  double depth = 0.0, from = 0.0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    depth = *arm_depth_;
    from = *arm_extension_;
  }
  const LeafClearanceParams& p = params_.leaves;
  const double dir = target_ext >= from ? 1.0 : -1.0;
  ++picks_cleared_;
  // Up to the leaf's level, through it past the boll, back off, down to the boll's top again.
  const std::pair<double, double> moves[] = {{nan, depth - p.leaf_clearance_m},
                                             {target_ext + dir * p.clear_overshoot_m, nan},
                                             {target_ext - dir * p.clear_standoff_m, nan},
                                             {nan, depth}};
  for (const auto& [x, z] : moves)
    if ((*result = moveArm(x, z, preempted)) != MoveResult::kDone) return target_ext;
  // Look again: the boll in full view is located on its whole top rather than on the part past the leaf.
  const auto observation = observe(preempted);
  if (!observation) return target_ext;
  const double target_x = target_ext + params_.arm_extension_zero_x_m;
  double best = p.redetect_radius_m, corrected = target_ext, corrected_depth = depth;
  for (const auto& b : observation->bolls) {
    const double d = std::hypot(b.position.x - target_x, b.position.y, b.position.z - depth);
    if (d < best) {
      best = d;
      corrected = b.position.x - params_.arm_extension_zero_x_m;
      corrected_depth = b.position.z;
    }
  }
  if (best < p.redetect_radius_m) {
    ++picks_redetected_;
    // A boll seen only at its side past the leaf was located deeper than its top: the housing goes to the top.
    if (std::abs(corrected_depth - depth) > 0.015) *result = moveArm(nan, corrected_depth, preempted);
  }
  return corrected;
}

void TopicHarvestPlant::onBolls(const cotton_harvester::BollArray::ConstPtr& msg) {
  std::lock_guard<std::mutex> lock(mutex_);
  bolls_ = msg;
  changed_.notify_all();
}

void TopicHarvestPlant::onEffector(const geometry_msgs::PointStamped::ConstPtr& msg) {
  std::lock_guard<std::mutex> lock(mutex_);
  effectors_.push_back(msg);
  while (effectors_.size() > 8) effectors_.pop_front();
  changed_.notify_all();
}

void TopicHarvestPlant::onRoverPosition(const std_msgs::Float64::ConstPtr& msg) {
  if (!std::isfinite(msg->data)) return;
  std::lock_guard<std::mutex> lock(mutex_);
  rover_position_ = msg->data;
  changed_.notify_all();
}

void TopicHarvestPlant::onJoints(const sensor_msgs::JointState::ConstPtr& msg) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (std::size_t i = 0; i < msg->name.size() && i < msg->position.size(); ++i) {
    if (!std::isfinite(msg->position[i])) continue;
    if (msg->name[i] == "horizontal") arm_extension_ = msg->position[i];
    if (msg->name[i] == "vertical") arm_depth_ = msg->position[i];
  }
  if (arm_extension_ && arm_depth_) {
    const ros::Time stamp = msg->header.stamp.isZero() ? ros::Time::now() : msg->header.stamp;
    if (!joint_history_.empty() && stamp < joint_history_.back().stamp) joint_history_.clear();  // clock reset
    joint_history_.push_back(JointSample{stamp, *arm_extension_, *arm_depth_});
    while (joint_history_.size() > 64) joint_history_.pop_front();
  }
  changed_.notify_all();
}

void TopicHarvestPlant::onBusy(const std_msgs::Bool::ConstPtr& msg) {
  std::lock_guard<std::mutex> lock(mutex_);
  arm_busy_ = msg->data;
  changed_.notify_all();
}

double TopicHarvestPlant::roverPositionM() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return rover_position_.value_or(0.0);
}

std::size_t TopicHarvestPlant::rejectedFrames() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return rejected_frames_;
}

bool TopicHarvestPlant::hasArmState() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return arm_extension_ && arm_depth_;
}

std::size_t TopicHarvestPlant::effectorFromCalibration() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return effector_from_calibration_;
}

std::string TopicHarvestPlant::check(const TopicPlantParams& p) {
  const std::pair<const char*, double> positive[] = {{"observe_timeout_s", p.observe_timeout_s},
                                                     {"effector_max_age_s", p.effector_max_age_s},
                                                     {"effector_stamp_tolerance_s", p.effector_stamp_tolerance_s},
                                                     {"joint_max_age_s", p.joint_max_age_s}};
  for (const auto& [key, v] : positive)
    if (!(v > 0.0) || !std::isfinite(v)) return std::string(key) + ": expected > 0";
  if (!std::isfinite(p.arm_y_m)) return "arm_y_m: expected a finite number";
  if (!(p.horizontal_min_m >= 0.0 && p.horizontal_min_m < p.horizontal_max_m && std::isfinite(p.horizontal_max_m)))
    return "horizontal_min_m, horizontal_max_m: expected 0 <= min < max";
  if (!(p.vertical_min_m >= 0.0 && p.vertical_min_m < p.vertical_max_m && std::isfinite(p.vertical_max_m)))
    return "vertical_min_m, vertical_max_m: expected 0 <= min < max";
  if (!std::isfinite(p.arm_extension_zero_x_m)) return "arm_extension_zero_x_m: expected a finite number";
  if (auto bad = p.canopy.check(); !bad.empty()) return "canopy/" + bad;
  return p.leaves.check();
}

template <typename Done>
bool TopicHarvestPlant::waitFor(Done done, double timeout_s, const Preempted& preempted, bool* was_preempted) {
  const ros::Time deadline = ros::Time::now() + ros::Duration(timeout_s);
  std::unique_lock<std::mutex> lock(mutex_);
  *was_preempted = false;
  while (ros::ok()) {
    if (done()) return true;
    if (preempted()) {
      *was_preempted = true;
      return false;
    }
    if (ros::Time::now() >= deadline) return false;
    changed_.wait_for(lock, std::chrono::milliseconds(20));
  }
  return false;
}

void TopicHarvestPlant::markActionEnd() {
  std::lock_guard<std::mutex> lock(mutex_);
  action_end_ = ros::Time::now();
}

geometry_msgs::PointStamped::ConstPtr TopicHarvestPlant::effectorOf(const ros::Time& stamp) const {
  for (auto it = effectors_.rbegin(); it != effectors_.rend(); ++it)
    if (std::abs(((*it)->header.stamp - stamp).toSec()) <= params_.effector_stamp_tolerance_s) return *it;
  return nullptr;
}

std::optional<Point3> TopicHarvestPlant::calibratedEffector(const ros::Time& stamp) const {
  const JointSample* best = nullptr;
  for (const auto& j : joint_history_)
    if (!best || std::abs((j.stamp - stamp).toSec()) < std::abs((best->stamp - stamp).toSec())) best = &j;
  if (!best || std::abs((best->stamp - stamp).toSec()) > params_.joint_max_age_s) return std::nullopt;
  return Point3{best->extension_m + params_.arm_extension_zero_x_m, params_.arm_y_m, best->depth_m};
}

HarvestObservation TopicHarvestPlant::makeObservation(const geometry_msgs::PointStamped::ConstPtr& effector) {
  HarvestObservation observation;
  observation.stamp_s = bolls_->header.stamp.toSec();
  observation.rover_position_m = rover_position_.value_or(0.0);
  for (const auto& boll : bolls_->bolls) {
    if (!std::isfinite(boll.position.x) || !std::isfinite(boll.position.y) || !std::isfinite(boll.position.z)) {
      ++rejected_frames_;
      continue;
    }
    observation.bolls.push_back(BollSighting{Point3{boll.position.x, boll.position.y, boll.position.z}, boll.confidence,
                                             static_cast<bool>(boll.reachable)});
  }
  if (effector && std::isfinite(effector->point.x) && std::isfinite(effector->point.y) &&
      std::isfinite(effector->point.z)) {
    observation.end_effector = Point3{effector->point.x, effector->point.y, effector->point.z};
  } else if (params_.effector_from_calibration) {
    observation.end_effector = calibratedEffector(bolls_->header.stamp);
    if (observation.end_effector) ++effector_from_calibration_;
  }
  last_used_stamp_ = bolls_->header.stamp;
  return observation;
}

std::optional<HarvestObservation> TopicHarvestPlant::observe(const Preempted& preempted) {
  bool was_preempted = false;
  ros::Time fresh_after;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    fresh_after = std::max(action_end_ + ros::Duration(params_.settle_s), last_used_stamp_ + ros::Duration(1e-6));
  }
  const auto fresh = [&] { return bolls_ && bolls_->header.stamp >= fresh_after; };
  if (!waitFor(fresh, params_.observe_timeout_s, preempted, &was_preempted)) {
    if (!was_preempted)
      ROS_WARN("harvest plant: no frame from perception (bolls) within %.1f s", params_.observe_timeout_s);
    return std::nullopt;
  }
  // The frame's own end effector follows its bolls; perception reports none when it did not find the housing,
  // which the next frame's bolls (or the wait's end) show.
  cotton_harvester::BollArray::ConstPtr frame;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    frame = bolls_;
  }
  const ros::Time stamp = frame->header.stamp;
  waitFor([&] { return effectorOf(stamp) || bolls_ != frame; }, params_.effector_max_age_s, preempted, &was_preempted);
  if (was_preempted) return std::nullopt;
  std::lock_guard<std::mutex> lock(mutex_);
  const auto effector = effectorOf(stamp);
  const cotton_harvester::BollArray::ConstPtr newest = bolls_;
  bolls_ = frame;  // the observation is of the frame waited for
  HarvestObservation observation = makeObservation(effector);
  if (newest->header.stamp > frame->header.stamp) bolls_ = newest;
  return observation;
}

MoveResult TopicHarvestPlant::moveRover(double distance_m, const Preempted& preempted) {
  double target = 0.0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!rover_position_) return MoveResult::kFailed;
    target = *rover_position_ + distance_m;
  }
  bool raise_arm = false;
  if (params_.rest_depth_m > 0.0) {
    std::lock_guard<std::mutex> lock(mutex_);
    raise_arm = arm_depth_ && *arm_depth_ > params_.rest_depth_m + params_.arm_tolerance_m;
    if (raise_arm) arm_busy_ = true;  // until the manipulator says otherwise after this command
  }
  if (raise_arm) {
    geometry_msgs::PointStamped up;
    up.header.stamp = ros::Time::now();
    up.header.frame_id = "manipulator";
    up.point.x = std::numeric_limits<double>::quiet_NaN();
    up.point.z = params_.rest_depth_m;
    arm_target_pub_.publish(up);
  }
  std_msgs::Float64 msg;
  msg.data = target;
  rover_target_pub_.publish(msg);
  const double timeout = params_.rover_timeout_s + params_.rover_timeout_per_m_s * std::abs(distance_m);
  // A short move must really happen: arrive within half of it when that is tighter than the tolerance.
  const double tolerance = std::min(params_.rover_tolerance_m, 0.5 * std::abs(distance_m));
  ros::Time inside_since;
  bool was_preempted = false;
  const bool arrived = waitFor(
      [&] {
        if (!rover_position_ || std::abs(*rover_position_ - target) > tolerance || (raise_arm && arm_busy_)) {
          inside_since = ros::Time();
          return false;
        }
        if (inside_since.isZero()) inside_since = ros::Time::now();
        return (ros::Time::now() - inside_since).toSec() >= params_.rover_settle_s;
      },
      timeout, preempted, &was_preempted);
  markActionEnd();
  if (was_preempted) return MoveResult::kPreempted;
  if (!arrived) {
    std::lock_guard<std::mutex> lock(mutex_);
    ROS_WARN("harvest plant: the rover did not settle at %.3f m within %.1f s: at %.3f m%s", target, timeout,
             rover_position_.value_or(std::nan("")), raise_arm && arm_busy_ ? ", the arm still rising" : "");
  }
  return arrived ? MoveResult::kDone : MoveResult::kFailed;
}

MoveResult TopicHarvestPlant::moveArm(double extension_m, double depth_m, const Preempted& preempted) {
  if (std::isfinite(extension_m))
    extension_m = std::clamp(extension_m, params_.horizontal_min_m, params_.horizontal_max_m);
  if (std::isfinite(depth_m)) depth_m = std::clamp(depth_m, params_.vertical_min_m, params_.vertical_max_m);
  geometry_msgs::PointStamped target;
  target.header.stamp = ros::Time::now();
  target.header.frame_id = "manipulator";
  target.point.x = extension_m;
  target.point.y = 0.0;
  target.point.z = depth_m;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    arm_busy_ = true;  // until the manipulator says otherwise after this command
  }
  arm_target_pub_.publish(target);
  bool was_preempted = false;
  const bool arrived = waitFor(
      [&] {
        const bool x_ok = !std::isfinite(extension_m) ||
                          (arm_extension_ && std::abs(*arm_extension_ - extension_m) <= params_.arm_tolerance_m);
        const bool z_ok =
            !std::isfinite(depth_m) || (arm_depth_ && std::abs(*arm_depth_ - depth_m) <= params_.arm_tolerance_m);
        return x_ok && z_ok && !arm_busy_;
      },
      params_.arm_timeout_s, preempted, &was_preempted);
  markActionEnd();
  if (was_preempted) return MoveResult::kPreempted;
  if (!arrived) {
    std::lock_guard<std::mutex> lock(mutex_);
    ROS_WARN("harvest plant: the arm did not reach (%.3f, %.3f) within %.1f s: at (%.3f, %.3f)%s", extension_m, depth_m,
             params_.arm_timeout_s, arm_extension_.value_or(std::nan("")), arm_depth_.value_or(std::nan("")),
             arm_busy_ ? ", still busy" : "");
  }
  return arrived ? MoveResult::kDone : MoveResult::kFailed;
}

MoveResult TopicHarvestPlant::moveArmToDepth(double depth_m, const Preempted& preempted) {
  return moveArm(std::numeric_limits<double>::quiet_NaN(), depth_m, preempted);
}

MoveResult TopicHarvestPlant::pick(double offset_m, const Preempted& preempted) {
  double start = 0.0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!arm_extension_) return MoveResult::kFailed;
    start = *arm_extension_;
  }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  double target = start + offset_m;
  if (params_.clear_leaves_before_pick) {
    double depth = 0.0;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      depth = arm_depth_.value_or(nan);
    }
    const double zero = params_.arm_extension_zero_x_m;
    if (std::isfinite(depth) &&
        pointsOverApproach(start + zero, target + zero, depth) >= params_.leaves.leaf_points_min) {
      MoveResult cleared = MoveResult::kDone;
      target = clearAndRelocate(target, preempted, &cleared);
      if (cleared != MoveResult::kDone) return cleared;
    }
  }
  MoveResult result = moveArm(target, nan, preempted);
  if (result != MoveResult::kDone) return result;
  std_msgs::Bool brush;
  brush.data = true;
  brush_pub_.publish(brush);
  bool was_preempted = false;
  waitFor([] { return false; }, params_.pick_dwell_s, preempted, &was_preempted);
  if (!params_.vacuum_while_retracting || was_preempted) {
    brush.data = false;
    brush_pub_.publish(brush);
    if (was_preempted) return MoveResult::kPreempted;
  }
  result = moveArm(start, nan, preempted);
  if (params_.vacuum_while_retracting) {
    brush.data = false;
    brush_pub_.publish(brush);
  }
  return result;
}

}  // namespace control
}  // namespace cotton_harvester
