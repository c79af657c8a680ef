// harvest_state_machine: the harvest machine of Algorithm 1 on thorvald_state_machine, driving the
// rover and the arm from the bolls and the end effector that perception reports. Publishes the
// machine's status (harvest/machine_status), the harvest metrics (harvest/metrics) and appends them
// to a CSV file when the run ends. Services harvest/start and harvest/stop (preempts).
#include <atomic>
#include <mutex>
#include <thread>

#include <diagnostic_msgs/DiagnosticStatus.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>
#include <visualization_msgs/MarkerArray.h>
#include <thorvald_state_machine/ros/status_publisher.h>

#include "cotton_harvester/control/harvest_machine.h"
#include "../ros/node_params.h"
#include "../ros/topic_harvest_plant.h"

namespace cotton_harvester {
namespace control {
namespace {

/// The harvest manoeuvres' parameters (HarvestActionParams, the same struct and defaults as the simulated rover's).
HarvestActionParams loadActionParams(const NodeParams& params) {
  HarvestActionParams p;
  ArmWorkspace& arm = p.arm;
  const std::pair<const char*, double*> numbers[] = {{"arm_extension_zero_x_m", &arm.extension_zero_x_m},
                                                     {"arm_y_m", &arm.strip_y_m},
                                                     {"horizontal_min_m", &arm.extension_min_m},
                                                     {"horizontal_max_m", &arm.extension_max_m},
                                                     {"vertical_min_m", &arm.min_depth_m},
                                                     {"vertical_max_m", &arm.max_depth_m},
                                                     {"rest_extension_m", &arm.rest_extension_m},
                                                     {"rest_depth_m", &arm.rest_depth_m},
                                                     {"pick_dwell_s", &p.pick_dwell_s},
                                                     {"leaf_clearance_m", &p.leaves.leaf_clearance_m},
                                                     {"clear_overshoot_m", &p.leaves.clear_overshoot_m},
                                                     {"clear_standoff_m", &p.leaves.clear_standoff_m},
                                                     {"redetect_radius_m", &p.leaves.redetect_radius_m},
                                                     {"effector_half_m", &p.leaves.effector_half_m},
                                                     {"search_strip_half_m", &p.canopy.strip_half_m},
                                                     {"search_boll_radius_m", &p.canopy.boll_radius_m},
                                                     {"search_min_cover_fraction", &p.canopy.min_cover_fraction},
                                                     {"search_layer_m", &p.canopy.layer_m},
                                                     {"search_above_layer_m", &p.canopy.above_layer_m},
                                                     {"search_housing_height_m", &p.canopy.housing_height_m},
                                                     {"search_push_m", &p.canopy.push_m}};
  for (const auto& [key, value] : numbers) *value = readDouble(params, key, *value);
  const std::pair<const char*, bool*> flags[] = {{"vacuum_while_retracting", &p.vacuum_while_retracting},
                                                 {"raise_after_pick", &p.raise_after_pick},
                                                 {"clear_leaves_before_pick", &p.clear_leaves_before_pick}};
  for (const auto& [key, value] : flags) *value = readBool(params, key, *value);
  p.leaves.leaf_points_min = readInt(params, "leaf_points_min", p.leaves.leaf_points_min, 1);
  p.canopy.max_passes = readInt(params, "search_max_passes", p.canopy.max_passes, 1);
  p.canopy.effector_half_m = p.leaves.effector_half_m;  // one housing
  return p;
}

HarvestParams loadHarvestParams(const NodeParams& params) {
  HarvestParams p;
  p.decision.y_tolerance_m = readDouble(params, "y_tolerance_m", p.decision.y_tolerance_m);
  p.decision.z_tolerance_m = readDouble(params, "z_tolerance_m", p.decision.z_tolerance_m);
  p.decision.pick_reach_m = readDouble(params, "pick_reach_m", p.decision.pick_reach_m);
  p.decision.y_forward_sign = readDouble(params, "y_forward_sign", p.decision.y_forward_sign);
  p.tracker.match_radius_m = readDouble(params, "match_radius_m", p.tracker.match_radius_m);
  p.tracker.max_pick_attempts = readInt(params, "max_pick_attempts", p.tracker.max_pick_attempts, 1);
  p.tracker.max_align_moves = readInt(params, "max_align_moves", p.tracker.max_align_moves, 1);
  const std::string order = readString(params, "target_order", "range");
  if (order != "range" && order != "along_row")
    throw ParamError(ros::this_node::getName() + ": target_order: expected range or along_row, got '" + order + "'");
  p.tracker.order = order == "along_row" ? TargetOrder::kAlongRow : TargetOrder::kRange;
  p.tracker.along_row_band_m = readDouble(params, "along_row_band_m", p.tracker.along_row_band_m);
  p.max_rover_step_m = readDouble(params, "max_rover_step_m", p.max_rover_step_m);
  p.pass_step_m = readDouble(params, "pass_step_m", p.pass_step_m);
  p.row_length_m = readDouble(params, "row_length_m", p.row_length_m);
  p.max_missed_observations = readInt(params, "max_missed_observations", p.max_missed_observations, 1);
  p.max_failed_actions = readInt(params, "max_failed_actions", p.max_failed_actions, 1);
  p.bolls_present = readInt(params, "bolls_present", p.bolls_present, 0);
  p.remember_target_frames = readInt(params, "remember_target_frames", p.remember_target_frames, 0);
  p.keep_target = readBool(params, "keep_target", p.keep_target);
  p.revisit_pending = readBool(params, "revisit_pending", p.revisit_pending);
  p.revisit_window_m = readDouble(params, "revisit_window_m", p.revisit_window_m);
  p.search_under_leaves = readBool(params, "search_under_leaves", p.search_under_leaves);
  p.search_spacing_m = readDouble(params, "search_spacing_m", p.search_spacing_m);
  p.actions = loadActionParams(params);
  requireSound(params, p.check());
  return p;
}

TopicPlantParams loadPlantParams(const NodeParams& params, const HarvestParams& harvest) {
  TopicPlantParams p;
  p.observe_timeout_s = readPositive(params, "observe_timeout_s", p.observe_timeout_s);
  p.settle_s = readDouble(params, "settle_s", p.settle_s);
  p.effector_max_age_s = readPositive(params, "effector_max_age_s", p.effector_max_age_s);
  p.rover_tolerance_m = readPositive(params, "rover_tolerance_m", p.rover_tolerance_m);
  p.rover_settle_s = readDouble(params, "rover_settle_s", p.rover_settle_s);
  p.rover_timeout_s = readPositive(params, "rover_timeout_s", p.rover_timeout_s);
  p.rover_timeout_per_m_s = readDouble(params, "rover_timeout_per_m_s", p.rover_timeout_per_m_s);
  p.arm_tolerance_m = readPositive(params, "arm_tolerance_m", p.arm_tolerance_m);
  p.arm_timeout_s = readPositive(params, "arm_timeout_s", p.arm_timeout_s);
  p.effector_stamp_tolerance_s = readPositive(params, "effector_stamp_tolerance_s", p.effector_stamp_tolerance_s);
  p.effector_from_calibration = readBool(params, "effector_from_calibration", p.effector_from_calibration);
  p.joint_max_age_s = readPositive(params, "joint_max_age_s", p.joint_max_age_s);
  p.cloud = harvest.actions.clear_leaves_before_pick || harvest.search_under_leaves;
  requireSound(params, TopicHarvestPlant::check(p));
  return p;
}

std::string number(const std::optional<double>& value) { return value ? std::to_string(*value) : "n/a"; }

class HarvestNode {
 public:
  HarvestNode(ros::NodeHandle& nh, ros::NodeHandle& pnh, const NodeParams& params)
      : harvest_(loadHarvestParams(params)),
        plant_(nh, loadPlantParams(params, harvest_), harvest_.actions.arm),
        machine_(plant_, harvest_),
        updater_(nh, pnh) {
    csv_path_ = readString(params, "metrics_csv", "");
    run_name_ = readString(params, "run_name", "harvest");
    const bool autostart = readBool(params, "autostart", true);
    ros::NodeHandle hnh(nh, "harvest");
    status_ = std::make_unique<thorvald_state_machine::StatusPublisher>(hnh, machine_.machine(), "machine_status", 1.0);
    metrics_pub_ = hnh.advertise<diagnostic_msgs::DiagnosticStatus>("metrics", 1, true);
    markers_pub_ = hnh.advertise<visualization_msgs::MarkerArray>("markers", 1);
    camera_frame_ = readString(params, "camera_frame", "camera");
    start_srv_ = hnh.advertiseService("start", &HarvestNode::onStart, this);
    stop_srv_ = hnh.advertiseService("stop", &HarvestNode::onStop, this);
    updater_.setHardwareID("none");
    updater_.add("harvest", this, &HarvestNode::diagnose);
    timer_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) {
      publishMetrics();
      publishMarkers();
      updater_.update();
    });
    if (autostart) start();
  }

  ~HarvestNode() {
    machine_.machine().requestPreempt();
    if (worker_.joinable()) worker_.join();
  }

 private:
  bool start() {
    if (running_) return false;
    if (worker_.joinable()) worker_.join();
    running_ = true;
    worker_ = std::thread([this] {
      std::string outcome, reason;
      try {
        outcome = machine_.run();
        if (outcome == "aborted") reason = machine_.abortReason();
      } catch (const std::exception& e) {
        outcome = "aborted";
        reason = std::string("harvest machine stopped: ") + e.what();
      }
      setOutcome(outcome, reason);
      if (reason.empty()) {
        ROS_INFO("harvest run '%s' ended: %s", run_name_.c_str(), outcome.c_str());
      } else {
        ROS_ERROR("harvest run '%s' ended: %s: %s", run_name_.c_str(), outcome.c_str(), reason.c_str());
      }
      publishMetrics();
      if (!csv_path_.empty()) {
        std::string error;
        const HarvestCounts counts = machine_.counts();
        if (!appendCsv(csv_path_, run_name_ + "_" + std::to_string(++runs_), counts, computeMetrics(counts), &error)) {
          ROS_ERROR("harvest metrics: %s", error.c_str());
        }
      }
      running_ = false;
    });
    return true;
  }

  bool onStart(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
    res.success = start();
    res.message = res.success ? "harvest started" : "a harvest is running";
    return true;
  }

  bool onStop(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
    res.success = running_;
    machine_.machine().requestPreempt();
    res.message = res.success ? "preemption requested" : "no harvest is running";
    return true;
  }

  std::string outcome() const {
    std::lock_guard<std::mutex> lock(outcome_mutex_);
    return outcome_;
  }
  /// The last run's outcome, with why it aborted when it did.
  std::string outcomeText() const {
    std::lock_guard<std::mutex> lock(outcome_mutex_);
    return abort_reason_.empty() ? outcome_ : outcome_ + ": " + abort_reason_;
  }
  void setOutcome(const std::string& outcome, const std::string& abort_reason) {
    std::lock_guard<std::mutex> lock(outcome_mutex_);
    outcome_ = outcome;
    abort_reason_ = abort_reason;
  }

  void publishMetrics() {
    const HarvestCounts counts = machine_.counts();
    const HarvestMetrics m = computeMetrics(counts);
    diagnostic_msgs::DiagnosticStatus msg;
    msg.name = "harvest_metrics";
    msg.hardware_id = run_name_;
    msg.level = diagnostic_msgs::DiagnosticStatus::OK;
    msg.message = running_ ? "running" : ("ended: " + outcomeText());
    auto add = [&msg](const std::string& key, const std::string& value) {
      diagnostic_msgs::KeyValue kv;
      kv.key = key;
      kv.value = value;
      msg.values.push_back(kv);
    };
    add("bolls_present", std::to_string(counts.bolls_present));
    add("detected", std::to_string(counts.detected));
    add("reached", std::to_string(counts.reached));
    add("picked", std::to_string(counts.picked));
    add("skipped", std::to_string(counts.skipped));
    add("pick_attempts", std::to_string(counts.pick_attempts));
    add("time_s", std::to_string(counts.time_s));
    add("distance_m", std::to_string(counts.distance_m));
    add("operation_velocity_cm_s", std::to_string(m.operation_velocity_cm_s));
    add("production_rate_bolls_s", std::to_string(m.production_rate_bolls_s));
    add("cycle_time_s", number(m.cycle_time_s));
    add("action_success_pct", number(m.action_success_pct));
    add("detection_performance_pct", number(m.detection_performance_pct));
    add("reaching_ratio_pct", number(m.reaching_ratio_pct));
    add("ee_fallback_frames", std::to_string(plant_.effectorFromCalibration()));
    add("frames_without_end_effector", std::to_string(machine_.rejectedFrames()));
    metrics_pub_.publish(msg);
  }

  /// The boll the machine is working on (green) and the end effector (orange), as last decided.
  void publishMarkers() {
    const auto points = machine_.lastDecisionPoints();
    if (!points) return;
    visualization_msgs::MarkerArray markers;
    const Point3* where[] = {&points->first, &points->second};
    const float colours[2][3] = {{0.1f, 0.9f, 0.1f}, {1.0f, 0.5f, 0.0f}};
    for (int i = 0; i < 2; ++i) {
      visualization_msgs::Marker m;
      m.header.stamp = ros::Time::now();
      m.header.frame_id = camera_frame_;
      m.ns = i == 0 ? "target_boll" : "end_effector";
      m.type = visualization_msgs::Marker::SPHERE;
      m.pose.position.x = where[i]->x;
      m.pose.position.y = where[i]->y;
      m.pose.position.z = where[i]->z;
      m.pose.orientation.w = 1.0;
      m.scale.x = m.scale.y = m.scale.z = 0.06;
      m.color.r = colours[i][0];
      m.color.g = colours[i][1];
      m.color.b = colours[i][2];
      m.color.a = 0.9f;
      m.lifetime = ros::Duration(2.0);
      markers.markers.push_back(m);
    }
    markers_pub_.publish(markers);
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& status) {
    const auto machine = machine_.machine().status();
    const std::string last = outcome();
    if (last == "aborted") {
      status.summary(diagnostic_msgs::DiagnosticStatus::ERROR, "harvest " + outcomeText());
    } else {
      status.summary(diagnostic_msgs::DiagnosticStatus::OK,
                     running_ ? "running " + machine.active_state : "idle (" + last + ")");
    }
    status.add("frames rejected (NaN points)", plant_.rejectedFrames());
    status.add("frames without end effector", machine_.rejectedFrames());
    status.add("end effector from the arm's calibration", plant_.effectorFromCalibration());
    status.add("picks that swept leaves aside first", machine_.actions().picksCleared());
    status.add("places searched under the leaves", machine_.actions().leafSearches());
    status.add("transitions", machine.transitions);
  }

  const HarvestParams harvest_;
  TopicHarvestPlant plant_;
  HarvestMachine machine_;
  diagnostic_updater::Updater updater_;
  std::unique_ptr<thorvald_state_machine::StatusPublisher> status_;
  std::string csv_path_, run_name_, camera_frame_;
  mutable std::mutex outcome_mutex_;
  std::string outcome_ = "not started";  ///< guarded by outcome_mutex_ (written by the machine's thread)
  std::string abort_reason_;             ///< guarded by outcome_mutex_
  std::atomic<bool> running_{false};
  int runs_ = 0;
  std::thread worker_;
  ros::Publisher metrics_pub_, markers_pub_;
  ros::ServiceServer start_srv_, stop_srv_;
  ros::WallTimer timer_;
};

}  // namespace
}  // namespace control
}  // namespace cotton_harvester

int main(int argc, char** argv) {
  ros::init(argc, argv, "harvest_state_machine");
  ros::NodeHandle nh, pnh("~");
  try {
    thorvald_common::ParamReader reader(pnh);
    reader.alsoRead("diagnostic_period");  // diagnostic_updater's own
    cotton_harvester::control::HarvestNode node(nh, pnh, cotton_harvester::control::NodeParams(reader));
    reader.finish();
    ros::AsyncSpinner spinner(2);
    spinner.start();
    ros::waitForShutdown();
  } catch (const std::exception& e) {
    ROS_FATAL("harvest_state_machine cannot start: %s", e.what());
    return 1;
  }
  return 0;
}
