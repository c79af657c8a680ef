#include "topic_harvest_plant.h"

#include <thorvald_base/ros/organised_cloud.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "thorvald_common/format.h"

namespace cotton_harvester {
namespace control {

using thorvald_common::format;

TopicHarvestPlant::TopicHarvestPlant(ros::NodeHandle& nh, const TopicPlantParams& params, const ArmWorkspace& arm)
    : params_(params), arm_(arm) {
  rover_target_pub_ = nh.advertise<std_msgs::Float64>("rover/position_target", 1, true);
  arm_target_pub_ = nh.advertise<geometry_msgs::PointStamped>("manipulator/target", 1, true);
  brush_pub_ = nh.advertise<std_msgs::Bool>("manipulator/brush", 1, true);
  bolls_sub_ = nh.subscribe("bolls", 2, &TopicHarvestPlant::onBolls, this);
  effector_sub_ = nh.subscribe("end_effector/position", 5, &TopicHarvestPlant::onEffector, this);
  rover_sub_ = nh.subscribe("rover/position", 5, &TopicHarvestPlant::onRoverPosition, this);
  joints_sub_ = nh.subscribe("manipulator/joint_states", 5, &TopicHarvestPlant::onJoints, this);
  busy_sub_ = nh.subscribe("manipulator/busy", 5, &TopicHarvestPlant::onBusy, this);
  if (params_.cloud) cloud_sub_ = nh.subscribe("camera/depth/points", 2, &TopicHarvestPlant::onCloud, this);
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
  thorvald_base::OrganisedCloudView checked;
  std::string error;
  if (!checked.reset(*cloud, &error)) return false;
  CloudView view;
  view.data = checked.data();
  view.rows = checked.height();
  view.cols = checked.width();
  view.row_step = checked.rowStep();
  view.point_step = checked.pointStep();
  view.x_offset = checked.offset(0);
  view.y_offset = checked.offset(1);
  view.z_offset = checked.offset(2);
  *keep = cloud;
  *out = view;
  return true;
}

std::optional<CameraCloud> TopicHarvestPlant::lastCloud(const Preempted& preempted) {
  if (!params_.cloud) return std::nullopt;
  // The frame's cloud may come a little after its bolls (11 MB at 1280 x 720).
  bool was_preempted = false;
  waitFor(
      [this] {
        return std::any_of(clouds_.begin(), clouds_.end(),
                           [this](const auto& c) { return c->header.stamp == last_used_stamp_; });
      },
      params_.observe_timeout_s, preempted, &was_preempted);
  if (was_preempted) return std::nullopt;
  sensor_msgs::PointCloud2::ConstPtr cloud;
  CameraCloud out;
  if (!observedCloud(&cloud, &out.view)) {
    ROS_WARN_THROTTLE(10.0, "harvest plant: no usable cloud of the observed frame on camera/depth/points");
    return std::nullopt;
  }
  out.fx_px = focalFromCloud(out.view);
  out.keep = std::shared_ptr<const void>(cloud.get(), [cloud](const void*) {});
  return out;
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

std::string TopicHarvestPlant::lastFailure() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return last_failure_;
}

void TopicHarvestPlant::noteFailure(const std::string& what) {
  ROS_WARN("harvest plant: %s", what.c_str());
  last_failure_ = what;
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
                                                     {"joint_max_age_s", p.joint_max_age_s},
                                                     {"rover_tolerance_m", p.rover_tolerance_m},
                                                     {"rover_timeout_s", p.rover_timeout_s},
                                                     {"arm_tolerance_m", p.arm_tolerance_m},
                                                     {"arm_timeout_s", p.arm_timeout_s}};
  for (const auto& [key, v] : positive)
    if (!(v > 0.0) || !std::isfinite(v)) return std::string(key) + ": expected > 0";
  const std::pair<const char*, double> non_negative[] = {{"settle_s", p.settle_s},
                                                         {"rover_settle_s", p.rover_settle_s},
                                                         {"rover_timeout_per_m_s", p.rover_timeout_per_m_s}};
  for (const auto& [key, v] : non_negative)
    if (!(v >= 0.0) || !std::isfinite(v)) return std::string(key) + ": expected >= 0";
  return "";
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
  return Point3{best->extension_m + arm_.extension_zero_x_m, arm_.strip_y_m, best->depth_m};
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
    if (!was_preempted) {
      std::lock_guard<std::mutex> lock(mutex_);
      noteFailure(format("no frame from perception (bolls) within %.1f s", params_.observe_timeout_s));
    }
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

MoveResult TopicHarvestPlant::moveRover(double distance_m, const ArmPose& arm, const Preempted& preempted) {
  const double timeout = params_.rover_timeout_s + params_.rover_timeout_per_m_s * std::abs(distance_m);
  const ros::Time start = ros::Time::now();
  bool was_preempted = false;
  // The move starts from the rover's position. The rover node reports it once the navigation controller's telemetry
  // comes, which can be after perception's first frames (it opens its port again every reconnect_period_s).
  const bool known = waitFor([this] { return rover_position_.has_value(); }, timeout, preempted, &was_preempted);
  if (was_preempted) return MoveResult::kPreempted;
  double target = 0.0;
  bool move_arm = false;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!known) {
      noteFailure(format("no rover position (rover/position) within %.1f s", timeout));
      return MoveResult::kFailed;
    }
    target = *rover_position_ + distance_m;
    // The arm moves only when an axis is asked elsewhere than where it is (an unknown axis is asked too).
    const auto away = [this](const std::optional<double>& at, double want) {
      return std::isfinite(want) && (!at || std::abs(*at - want) > params_.arm_tolerance_m);
    };
    move_arm = away(arm_extension_, arm.extension_m) || away(arm_depth_, arm.depth_m);
  }
  if (move_arm) commandArm(arm);
  std_msgs::Float64 msg;
  msg.data = target;
  rover_target_pub_.publish(msg);
  // A short move must really happen: arrive within half of it when that is tighter than the tolerance.
  const double tolerance = std::min(params_.rover_tolerance_m, 0.5 * std::abs(distance_m));
  ros::Time inside_since;
  const bool arrived = waitFor(
      [&] {
        if (!rover_position_ || std::abs(*rover_position_ - target) > tolerance || (move_arm && !armAt(arm))) {
          inside_since = ros::Time();
          return false;
        }
        if (inside_since.isZero()) inside_since = ros::Time::now();
        return (ros::Time::now() - inside_since).toSec() >= params_.rover_settle_s;
      },
      timeout - (ros::Time::now() - start).toSec(), preempted, &was_preempted);
  markActionEnd();
  if (was_preempted) return MoveResult::kPreempted;
  if (!arrived) {
    std::lock_guard<std::mutex> lock(mutex_);
    noteFailure(format("the rover did not settle at %.3f m within %.1f s: at %.3f m%s", target, timeout,
                       rover_position_.value_or(std::nan("")),
                       move_arm && !armAt(arm) ? ", the arm still moving" : ""));
  }
  return arrived ? MoveResult::kDone : MoveResult::kFailed;
}

void TopicHarvestPlant::commandArm(const ArmPose& pose) {
  geometry_msgs::PointStamped target;
  target.header.stamp = ros::Time::now();
  target.header.frame_id = "manipulator";
  target.point.x = pose.extension_m;
  target.point.y = 0.0;
  target.point.z = pose.depth_m;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    arm_busy_ = true;  // until the manipulator says otherwise after this command
  }
  arm_target_pub_.publish(target);
}

bool TopicHarvestPlant::armAt(const ArmPose& target) const {
  const bool x_ok = !std::isfinite(target.extension_m) ||
                    (arm_extension_ && std::abs(*arm_extension_ - target.extension_m) <= params_.arm_tolerance_m);
  const bool z_ok = !std::isfinite(target.depth_m) ||
                    (arm_depth_ && std::abs(*arm_depth_ - target.depth_m) <= params_.arm_tolerance_m);
  return x_ok && z_ok && !arm_busy_;
}

MoveResult TopicHarvestPlant::moveArm(const ArmPose& target, const Preempted& preempted) {
  commandArm(target);
  bool was_preempted = false;
  const bool arrived = waitFor([&] { return armAt(target); }, params_.arm_timeout_s, preempted, &was_preempted);
  markActionEnd();
  if (was_preempted) return MoveResult::kPreempted;
  if (!arrived) {
    std::lock_guard<std::mutex> lock(mutex_);
    noteFailure(format("the arm did not reach (%.3f, %.3f) within %.1f s: at (%.3f, %.3f)%s", target.extension_m,
                       target.depth_m, params_.arm_timeout_s, arm_extension_.value_or(std::nan("")),
                       arm_depth_.value_or(std::nan("")), arm_busy_ ? ", still busy" : ""));
  }
  return arrived ? MoveResult::kDone : MoveResult::kFailed;
}

std::optional<ArmPose> TopicHarvestPlant::armPose() const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!arm_extension_ || !arm_depth_) return std::nullopt;
  return ArmPose{*arm_extension_, *arm_depth_};
}

void TopicHarvestPlant::setVacuum(bool on) {
  std_msgs::Bool brush;
  brush.data = on;
  brush_pub_.publish(brush);
}

MoveResult TopicHarvestPlant::wait(double seconds, const Preempted& preempted) {
  bool was_preempted = false;
  waitFor([] { return false; }, seconds, preempted, &was_preempted);
  return was_preempted ? MoveResult::kPreempted : MoveResult::kDone;
}

}  // namespace control
}  // namespace cotton_harvester
