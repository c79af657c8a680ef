// rail_detector: estimates base_link's pose in the rail frame from the depth camera (paper Algorithm 1),
// gates inconsistent estimates, and calibrates the camera mount on request (paper §V-C).
#include <chrono>
#include <cmath>
#include <optional>

#include <diagnostic_updater/diagnostic_updater.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <ros/ros.h>
#include <std_msgs/Bool.h>
#include <thorvald_common/ros/param_reader.h>
#include <thorvald_common/ros/run_node.h>
#include <std_srvs/Trigger.h>
#include <tf2_geometry_msgs/tf2_geometry_msgs.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <visualization_msgs/MarkerArray.h>

#include "cloud_messages.h"
#include "thorvald_map/ros/conversions.h"
#include "greenhouse_rail_nav/RailDetectionStatus.h"
#include "greenhouse_rail_nav/mount_calibration.h"
#include "greenhouse_rail_nav/rail_detector.h"
#include "greenhouse_rail_nav/rail_pose_gate.h"

namespace greenhouse_rail_nav {
namespace {

struct NodeSettings {
  std::string base_frame = "base_link";
  std::string rail_frame = "rail";      ///< frame_id of the published pose (base_link in the rail frame)
  std::string fit_method = "clusters";  ///< clusters (the paper) or ransac (the baseline)
  double tf_timeout_s = 0.05;
  std::string calibration_file;  ///< where the mount correction is kept; empty: not persisted
  /// Detect from the start; `~enable` (std_msgs/Bool) switches detection on and off: off, the node unsubscribes from
  /// the cloud (a camera driver or the simulator that publishes only to subscribers then stops as well).
  bool enabled = true;
  double calibration_max_y_m = 0.10, calibration_max_yaw_rad = 0.10, calibration_max_age_s = 1.0;
  RailDetectorParams detector;
  RailPoseGateParams gate;
};

/// Reads and checks every private parameter; throws thorvald_common::ParamError naming the bad one.
NodeSettings loadSettings(const ros::NodeHandle& pnh) {
  using thorvald_common::ParamRange;
  thorvald_common::ParamReader r(pnh);
  NodeSettings s;
  const ParamRange positive = ParamRange::above(0.0);
  s.base_frame = r.text("base_frame", s.base_frame);
  s.rail_frame = r.text("rail_frame", s.rail_frame);
  s.fit_method = r.choice("fit_method", s.fit_method, {"clusters", "ransac"});
  s.tf_timeout_s = r.number("tf_timeout_s", s.tf_timeout_s, ParamRange::closed(0.0, 10.0), "s");
  s.calibration_file = r.text("calibration_file", s.calibration_file);
  s.enabled = r.flag("enabled", s.enabled);
  s.calibration_max_y_m = r.number("calibration_max_y_m", s.calibration_max_y_m, positive, "m");
  s.calibration_max_yaw_rad = r.number("calibration_max_yaw_rad", s.calibration_max_yaw_rad, positive, "rad");
  s.calibration_max_age_s = r.number("calibration_max_age_s", s.calibration_max_age_s, positive, "s");
  auto& d = s.detector;
  d.rail_gauge_m = r.number("rail_gauge_m", d.rail_gauge_m, ParamRange::aboveUpTo(0.0, 3.0), "m");
  d.gauge_tolerance_m = r.number("gauge_tolerance_m", d.gauge_tolerance_m, positive, "m");
  d.depth_median_px = r.integer("depth_median_px", d.depth_median_px, 0, 15);
  d.pipe_hole_height_m = r.number("pipe_hole_height_m", d.pipe_hole_height_m, ParamRange::closed(0.0, 1.0), "m");
  d.crop_z_min_m = r.number("crop_z_min_m", d.crop_z_min_m, ParamRange::closed(-1.0, 1.0), "m");
  d.crop_z_max_m = r.number("crop_z_max_m", d.crop_z_max_m, ParamRange::closed(-1.0, 1.0), "m");
  d.crop_x_min_m = r.number("crop_x_min_m", d.crop_x_min_m, ParamRange::closed(-10.0, 20.0), "m");
  d.crop_x_max_m = r.number("crop_x_max_m", d.crop_x_max_m, ParamRange::closed(-10.0, 20.0), "m");
  d.crop_y_max_m = r.number("crop_y_max_m", d.crop_y_max_m, ParamRange::aboveUpTo(0.0, 10.0), "m");
  d.voxel_size_m = r.number("voxel_size_m", d.voxel_size_m, ParamRange::closed(0.0, 1.0), "m");
  d.cluster_tolerance_m = r.number("cluster_tolerance_m", d.cluster_tolerance_m, ParamRange::aboveUpTo(0.0, 1.0), "m");
  d.min_cluster_points = r.integer("min_cluster_points", d.min_cluster_points, 3, 10000000);
  d.max_cluster_points = r.integer("max_cluster_points", d.max_cluster_points, 3, 100000000);
  d.min_line_length_m = r.number("min_line_length_m", d.min_line_length_m, positive, "m");
  d.min_linearity = r.number("min_linearity", d.min_linearity, ParamRange{0.0, 1.0, true, true});
  d.rail_trim_m = r.number("rail_trim_m", d.rail_trim_m, positive, "m");
  d.height_tolerance_m = r.number("height_tolerance_m", d.height_tolerance_m, positive, "m");
  d.min_partner_coverage = r.number("min_partner_coverage", d.min_partner_coverage, ParamRange::closed(0.0, 1.0));
  d.parallel_tolerance_rad = r.number("parallel_tolerance_rad", d.parallel_tolerance_rad, positive, "rad");
  d.max_abs_yaw_rad = r.number("max_abs_yaw_rad", d.max_abs_yaw_rad, ParamRange{0.0, M_PI / 2, true, true}, "rad");
  d.max_lateral_offset_m = r.number("max_lateral_offset_m", d.max_lateral_offset_m, positive, "m");
  d.ransac_distance_m = r.number("ransac_distance_m", d.ransac_distance_m, positive, "m");
  d.ransac_max_lines = r.integer("ransac_max_lines", d.ransac_max_lines, 2, 100);
  d.ransac_iterations = r.integer("ransac_iterations", d.ransac_iterations, 1, 1000000);
  d.sigma_x_m = r.number("sigma_x_m", d.sigma_x_m, positive, "m");
  d.sigma_y_m = r.number("sigma_y_m", d.sigma_y_m, positive, "m");
  d.sigma_yaw_rad = r.number("sigma_yaw_rad", d.sigma_yaw_rad, positive, "rad");
  d.start_view_margin_m =
      r.number("start_view_margin_m", d.start_view_margin_m, ParamRange{0.0, 1.0, false, true}, "m");
  d.image_margin_px = r.number("image_margin_px", d.image_margin_px, ParamRange{0.0, 100.0, false, true}, "px");
  d.unobserved_sigma_x_m = r.number("unobserved_sigma_x_m", d.unobserved_sigma_x_m, positive, "m");
  d.pipe_radius_m = r.number("pipe_radius_m", d.pipe_radius_m, ParamRange{0.0, 0.2, false, true}, "m");
  s.gate.max_step_xy_m = r.number("gate_max_step_xy_m", s.gate.max_step_xy_m, positive, "m");
  s.gate.max_step_yaw_rad = r.number("gate_max_step_yaw_rad", s.gate.max_step_yaw_rad, positive, "rad");
  s.gate.frames_to_accept_jump = r.integer("gate_frames_to_accept_jump", s.gate.frames_to_accept_jump, 1, 1000);
  s.gate.reset_after_s = r.number("gate_reset_after_s", s.gate.reset_after_s, positive, "s");
  r.alsoRead("diagnostic_period");
  // Checks across parameters (e.g. crop_z_min_m < crop_z_max_m): the library's own validation.
  for (const std::string& error : {d.validate(), s.gate.validate()})
    if (!error.empty()) throw thorvald_common::ParamError(r.node() + ": " + error);
  if (s.base_frame.empty() || s.rail_frame.empty())
    throw thorvald_common::ParamError(r.node() + ": base_frame and rail_frame must not be empty");
  r.finish();
  return s;
}

Eigen::Isometry3d toEigen(const geometry_msgs::Transform& t) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  out.linear() = Eigen::Quaterniond(t.rotation.w, t.rotation.x, t.rotation.y, t.rotation.z).toRotationMatrix();
  out.translation() = Eigen::Vector3d(t.translation.x, t.translation.y, t.translation.z);
  return out;
}

class RailDetectorNode {
 public:
  RailDetectorNode(ros::NodeHandle& nh, ros::NodeHandle& pnh, const NodeSettings& settings)
      : settings_(settings),
        detector_(settings.detector),
        gate_(settings.gate),
        tf_listener_(tf_buffer_),
        updater_(nh, pnh) {
    loadCalibration();
    pose_pub_ = nh.advertise<geometry_msgs::PoseWithCovarianceStamped>("rail_pose", 5);
    status_pub_ = nh.advertise<greenhouse_rail_nav::RailDetectionStatus>("rail_detection", 5);
    markers_pub_ = pnh.advertise<visualization_msgs::MarkerArray>("markers", 1);
    calibrate_srv_ = pnh.advertiseService("calibrate_mount", &RailDetectorNode::onCalibrate, this);
    nh_ = nh;
    enable(settings_.enabled);
    enable_sub_ =
        pnh.subscribe<std_msgs::Bool>("enable", 1, [this](const std_msgs::BoolConstPtr& m) { enable(m->data); });
    updater_.setHardwareID("rail_detector");
    updater_.add("rail detection", this, &RailDetectorNode::diagnose);
    diag_timer_ = nh.createTimer(ros::Duration(1.0), [this](const ros::TimerEvent&) { updater_.update(); });
  }

 private:
  void loadCalibration() {
    if (settings_.calibration_file.empty()) return;
    std::string error;
    MountCorrection loaded;
    if (loadMountCorrection(settings_.calibration_file, &loaded, &error)) {
      correction_ = loaded;
      ROS_INFO("rail_detector: mount correction y %.4f m, yaw %.4f rad from %s", loaded.y_m, loaded.yaw_rad,
               settings_.calibration_file.c_str());
    } else {
      ROS_WARN_STREAM("rail_detector: no mount correction applied (" << error << ")");
    }
  }

  void onCloud(const sensor_msgs::PointCloud2::ConstPtr& msg) {
    ++clouds_;
    greenhouse_rail_nav::RailDetectionStatus status;
    status.header = msg->header;
    OrganisedCloud cloud;
    std::string error;
    if (!fromMessage(*msg, &cloud, &error)) {
      finish(&status, greenhouse_rail_nav::RailDetectionStatus::BAD_INPUT, "malformed cloud: " + error);
      return;
    }
    Eigen::Isometry3d camera_in_base;
    try {
      camera_in_base = toEigen(tf_buffer_
                                   .lookupTransform(settings_.base_frame, msg->header.frame_id, msg->header.stamp,
                                                    ros::Duration(settings_.tf_timeout_s))
                                   .transform);
    } catch (const tf2::TransformException& e) {
      finish(&status, greenhouse_rail_nav::RailDetectionStatus::NO_TRANSFORM, std::string("no transform: ") + e.what());
      return;
    }
    const auto t0 = std::chrono::steady_clock::now();
    const RailDetection d = detector_.detect(
        cloud, camera_in_base, correction_.asTransform(),
        settings_.fit_method == "ransac" ? RailFitMethod::kRansacBaseline : RailFitMethod::kClusterLines);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    mean_ms_ = mean_ms_ == 0.0 ? ms : 0.95 * mean_ms_ + 0.05 * ms;
    status.points_in_band = static_cast<std::uint32_t>(d.points_in_band);
    status.clusters = static_cast<std::uint32_t>(d.clusters);
    status.lines = static_cast<std::uint32_t>(d.lines);
    if (d.status == RailDetection::Status::kBadInput) {
      finish(&status, greenhouse_rail_nav::RailDetectionStatus::BAD_INPUT, d.reason);
      return;
    }
    if (!d.found()) {
      finish(&status, greenhouse_rail_nav::RailDetectionStatus::NOT_FOUND, d.reason);
      return;
    }
    last_uncorrected_ = correction_.asTransform().inverse() * d.rail_in_base;
    last_found_stamp_ = msg->header.stamp;
    status.x = d.base_in_rail.x;
    status.y = d.base_in_rail.y;
    status.yaw = d.base_in_rail.yaw;
    status.fit_score = d.fit_score;
    publishMarkers(d, msg->header.stamp);
    const auto verdict = gate_.update(d.base_in_rail, msg->header.stamp.toSec());
    if (verdict == RailPoseGate::Verdict::kHeldBack) {
      finish(&status, greenhouse_rail_nav::RailDetectionStatus::HELD_BACK,
             "inconsistent with the previous estimate (" + std::to_string(gate_.heldBack()) + " held back)");
      return;
    }
    geometry_msgs::PoseWithCovarianceStamped pose;
    pose.header.stamp = msg->header.stamp;
    pose.header.frame_id = settings_.rail_frame;
    pose.pose.pose = thorvald_map::toPose(d.base_in_rail);
    pose.pose.covariance.fill(0.0);
    pose.pose.covariance[0] = d.variance[0];
    pose.pose.covariance[7] = d.variance[1];
    pose.pose.covariance[14] = pose.pose.covariance[21] = pose.pose.covariance[28] = 1e3;  // z, roll, pitch: not seen
    pose.pose.covariance[35] = d.variance[2];
    pose_pub_.publish(pose);
    finish(&status,
           d.xObserved() ? greenhouse_rail_nav::RailDetectionStatus::FOUND
                         : greenhouse_rail_nav::RailDetectionStatus::FOUND_X_UNOBSERVED,
           d.reason + (verdict == RailPoseGate::Verdict::kAcceptedJump ? " (jump accepted)" : ""));
  }

  void finish(greenhouse_rail_nav::RailDetectionStatus* status, std::uint8_t code, const std::string& reason) {
    status->status = code;
    status->reason = reason;
    ++counts_[code];
    last_code_ = code;
    last_reason_ = reason;
    status_pub_.publish(*status);
  }

  void publishMarkers(const RailDetection& d, const ros::Time& stamp) {
    using visualization_msgs::Marker;
    visualization_msgs::MarkerArray array;
    Marker rails;
    rails.header.frame_id = settings_.base_frame;
    rails.header.stamp = stamp;
    rails.ns = "rails";
    rails.type = Marker::LINE_LIST;
    rails.pose.orientation.w = 1.0;
    rails.scale.x = 0.03;
    rails.color.g = 1.0f;
    rails.color.a = 1.0f;
    for (const auto& rail : d.rails) {
      for (const double s : {rail.near_end, rail.fit.s_max}) {
        geometry_msgs::Point p;
        const Eigen::Vector2d q = rail.fit.centroid + s * rail.fit.direction;
        p.x = q.x();
        p.y = q.y();
        p.z = 0.05;
        rails.points.push_back(p);
      }
    }
    Marker frame = rails;
    frame.ns = "rail_frame";
    frame.type = Marker::ARROW;
    frame.points.clear();
    frame.scale.x = 0.5;
    frame.scale.y = frame.scale.z = 0.05;
    frame.color.r = 1.0f;
    frame.color.g = 0.0f;
    frame.pose = thorvald_map::toPose(d.rail_in_base);
    array.markers = {rails, frame};
    markers_pub_.publish(array);
  }

  bool onCalibrate(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
    if (!last_uncorrected_ || (ros::Time::now() - last_found_stamp_).toSec() > settings_.calibration_max_age_s) {
      res.success = false;
      res.message = "no rails seen in the last " + std::to_string(settings_.calibration_max_age_s) +
                    " s: place the robot on the rails, facing along them, in view of the rails";
      return true;
    }
    MountCorrection correction;
    std::string error;
    if (!computeMountCorrection(*last_uncorrected_, settings_.calibration_max_y_m, settings_.calibration_max_yaw_rad,
                                &correction, &error)) {
      res.success = false;
      res.message = error;
      return true;
    }
    if (!settings_.calibration_file.empty() && !saveMountCorrection(correction, settings_.calibration_file, &error)) {
      res.success = false;
      res.message = error + " (correction not applied)";
      return true;
    }
    correction_ = correction;
    gate_.reset();
    res.success = true;
    res.message = "mount correction y " + std::to_string(correction.y_m) + " m, yaw " +
                  std::to_string(correction.yaw_rad) + " rad" +
                  (settings_.calibration_file.empty() ? " (not persisted: calibration_file is empty)"
                                                      : ", saved to " + settings_.calibration_file);
    ROS_INFO_STREAM("rail_detector: " << res.message);
    return true;
  }

  void enable(bool on) {
    if (on == static_cast<bool>(cloud_sub_)) return;
    if (on) {
      // Frames from before the pause describe another pose: the gate starts afresh.
      gate_.reset();
      cloud_sub_ = nh_.subscribe("camera/depth/points", 1, &RailDetectorNode::onCloud, this);
    } else {
      cloud_sub_.shutdown();
    }
    ROS_INFO("rail_detector: detection %s", on ? "on" : "off (~enable): not subscribed to camera/depth/points");
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
    using diagnostic_msgs::DiagnosticStatus;
    using Msg = greenhouse_rail_nav::RailDetectionStatus;
    if (!cloud_sub_) {
      stat.summary(DiagnosticStatus::OK, "off (~enable false): not detecting");
    } else if (clouds_ == 0) {
      stat.summary(DiagnosticStatus::WARN, "no cloud received on camera/depth/points");
    } else if (last_code_ == Msg::FOUND || last_code_ == Msg::FOUND_X_UNOBSERVED) {
      stat.summary(DiagnosticStatus::OK, last_reason_);
    } else {
      stat.summary(last_code_ == Msg::NO_TRANSFORM ? DiagnosticStatus::ERROR : DiagnosticStatus::WARN, last_reason_);
    }
    stat.add("clouds", clouds_);
    stat.add("found", counts_[Msg::FOUND]);
    stat.add("found, start out of view", counts_[Msg::FOUND_X_UNOBSERVED]);
    stat.add("held back", counts_[Msg::HELD_BACK]);
    stat.add("not found", counts_[Msg::NOT_FOUND]);
    stat.add("bad input", counts_[Msg::BAD_INPUT]);
    stat.add("no transform", counts_[Msg::NO_TRANSFORM]);
    stat.add("mean detection time [ms]", mean_ms_);
    stat.add("mount correction y [m]", correction_.y_m);
    stat.add("mount correction yaw [rad]", correction_.yaw_rad);
  }

  NodeSettings settings_;
  RailDetector detector_;
  RailPoseGate gate_;
  MountCorrection correction_;
  std::optional<thorvald_base::Pose2D> last_uncorrected_;
  ros::Time last_found_stamp_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  diagnostic_updater::Updater updater_;
  ros::Publisher pose_pub_, status_pub_, markers_pub_;
  ros::NodeHandle nh_;
  ros::Subscriber cloud_sub_, enable_sub_;
  ros::ServiceServer calibrate_srv_;
  ros::Timer diag_timer_;
  std::size_t clouds_ = 0;
  std::size_t counts_[6] = {0, 0, 0, 0, 0, 0};
  std::uint8_t last_code_ = 0;
  double mean_ms_ = 0.0;
  std::string last_reason_;
};

}  // namespace
}  // namespace greenhouse_rail_nav

int main(int argc, char** argv) {
  return thorvald_common::runNode(argc, argv, "rail_detector", [](ros::NodeHandle& nh, ros::NodeHandle& pnh) {
    return std::make_shared<greenhouse_rail_nav::RailDetectorNode>(nh, pnh, greenhouse_rail_nav::loadSettings(pnh));
  });
}
