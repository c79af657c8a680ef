// odom_fusion: planar EKF fusing wheel odometry twists with an IMU's yaw rate (and yaw), a stand-in for
// robot_localization's ekf_localization_node with its parameter names for what it supports. Thin shell around
// PlanarEkf.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <diagnostic_updater/diagnostic_updater.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>
#include <tf2_ros/transform_broadcaster.h>
#include <thorvald_common/ros/param_reader.h>

#include "ekf_settings.h"
#include "ros_conversions.h"
#include "thorvald_navigation/planar_ekf.h"

namespace thorvald_navigation {
namespace {

// robot_localization's 15-entry sensor configuration: x y z, roll pitch yaw, vx vy vz, vroll vpitch vyaw, ax ay az.
constexpr const char* kConfigNames[15] = {"x",  "y",     "z",      "roll", "pitch", "yaw", "vx", "vy",
                                          "vz", "vroll", "vpitch", "vyaw", "ax",    "ay",  "az"};
// 15-state index -> planar state index (-1: not a planar state).
constexpr int kPlanarIndex[15] = {kX, kY, -1, -1, -1, kYaw, kVx, kVy, -1, -1, -1, kVyaw, -1, -1, -1};

struct SensorSettings {
  std::string topic;  // empty: sensor not used
  std::array<bool, 6> mask{};
  bool relative = false;
};

struct Settings {
  double frequency = 30.0;
  bool two_d_mode = true;
  bool publish_tf = true;
  std::string odom_frame = "odom", base_link_frame = "base_link", world_frame = "odom", map_frame = "map";
  double sensor_timeout = 0.1;
  SensorSettings odom0, imu0;
  /// Mahalanobis gates [sigma] (robot_localization's *_rejection_threshold; infinity: none): the wheel twist, the
  /// IMU's yaw and its yaw rate. Against the gyro, the twist of wheels that slip or push against something.
  double odom0_twist_gate = std::numeric_limits<double>::infinity();
  double imu0_pose_gate = std::numeric_limits<double>::infinity();
  double imu0_rate_gate = std::numeric_limits<double>::infinity();
  State6 process_noise;
  State6 initial_covariance;
  double min_variance = 1e-6;
};

// Parses an odomN/imuN config; `allowed` lists the 15-state entries the sensor may feed.
std::string parseConfig(const std::vector<bool>& cfg, const std::string& name, const std::vector<int>& allowed,
                        bool two_d_mode, std::array<bool, 6>* mask) {
  if (cfg.size() != 15)
    return name + " must have 15 entries (x y z roll pitch yaw vx vy vz vroll vpitch vyaw ax ay az)";
  mask->fill(false);
  for (int i = 0; i < 15; ++i) {
    if (!cfg[i]) continue;
    const bool out_of_plane = kPlanarIndex[i] < 0 && i < 12;
    if (out_of_plane && two_d_mode) continue;  // ignored in 2D mode, as robot_localization does
    bool ok = false;
    for (int a : allowed) ok = ok || a == i;
    if (!ok)
      return name + ": fusing '" + kConfigNames[i] +
             "' from this sensor is not supported (supported: odometry vx vy vyaw; IMU yaw vyaw)";
    (*mask)[kPlanarIndex[i]] = true;
  }
  return {};
}

/// Reads and checks the node's parameters; false with the reason in `error` when one is wrong.
bool loadSettings(const ros::NodeHandle& pnh, Settings* s, std::string* error) {
  using R = thorvald_common::ParamRange;
  auto check = [](const std::string& problem) {
    if (!problem.empty()) throw thorvald_common::ParamError("odom_fusion: " + problem);
  };
  try {
    thorvald_common::ParamReader r(pnh, "odom_fusion");
    s->frequency = r.number("frequency", s->frequency, R::aboveUpTo(0.0, 1000.0), "Hz");
    s->two_d_mode = r.flag("two_d_mode", s->two_d_mode);
    s->publish_tf = r.flag("publish_tf", s->publish_tf);
    s->odom_frame = r.text("odom_frame", s->odom_frame);
    s->base_link_frame = r.text("base_link_frame", s->base_link_frame);
    s->world_frame = r.text("world_frame", s->world_frame);
    s->map_frame = r.text("map_frame", s->map_frame);
    s->sensor_timeout = r.number("sensor_timeout", s->sensor_timeout, R::above(0.0), "s");
    s->odom0.topic = r.text("odom0", s->odom0.topic);
    s->imu0.topic = r.text("imu0", s->imu0.topic);
    s->imu0.relative = r.flag("imu0_relative", s->imu0.relative);
    std::vector<bool> odom_cfg(15, false), imu_cfg(15, false);
    odom_cfg[6] = odom_cfg[7] = odom_cfg[11] = true;
    imu_cfg[11] = true;
    odom_cfg = r.flags("odom0_config", odom_cfg, 15, 15);
    imu_cfg = r.flags("imu0_config", imu_cfg, 15, 15);
    const std::vector<double> q = r.numbers("process_noise_covariance", {}, R::any(), "", 0, 225);
    const std::vector<double> p0 = r.numbers("initial_estimate_covariance", {}, R::any(), "", 0, 225);
    for (const char* key : {"odom1", "odom2", "imu1", "imu2", "pose0", "pose1", "twist0", "twist1"})
      r.reject(key, "only one odometry (odom0) and one IMU (imu0) input are supported");
    for (const char* key : {"odom0_differential", "imu0_differential", "odom0_relative", "use_control",
                            "control_config", "smooth_lagged_data", "history_length",
                            "dynamic_process_noise_covariance", "imu0_remove_gravitational_acceleration"})
      r.reject(key, "this option of robot_localization is not implemented here");
    // Tuning of robot_localization's own machinery: accepted, has no meaning here.
    for (const char* key :
         {"odom0_queue_size", "imu0_queue_size", "print_diagnostics", "debug", "transform_time_offset",
          "transform_timeout", "odom0_nodelay", "imu0_nodelay", "publish_acceleration"})
      r.alsoRead(key);
    // Gates of what is fused here (odom0's pose and the IMU's acceleration are not: their gates have no effect).
    s->odom0_twist_gate = readRejectionThreshold(r, "odom0_twist_rejection_threshold");
    s->imu0_pose_gate = readRejectionThreshold(r, "imu0_pose_rejection_threshold");
    s->imu0_rate_gate = readImuRateRejectionThreshold(r, "imu0");
    for (const char* key : {"odom0_pose_rejection_threshold", "imu0_linear_acceleration_rejection_threshold"})
      r.alsoRead(key);
    r.finish();
    if (!s->two_d_mode) check("~two_d_mode: false is not supported (this filter is planar)");
    if (s->world_frame != s->odom_frame)
      check("~world_frame must equal ~odom_frame: map-frame fusion belongs to map_localizer");
    if (s->odom0.topic.empty()) check("~odom0 (wheel odometry topic) must be set");
    check(parseConfig(odom_cfg, "odom0_config", {6, 7, 11}, s->two_d_mode, &s->odom0.mask));
    check(parseConfig(imu_cfg, "imu0_config", {5, 11}, s->two_d_mode, &s->imu0.mask));
    if (!s->odom0.mask[kVyaw] && (s->imu0.topic.empty() || !(s->imu0.mask[kYaw] || s->imu0.mask[kVyaw])))
      check("nothing gives the heading: odom0_config leaves the wheels' vyaw out and no imu0 with yaw or vyaw is set");
    auto diagonal = [&](const std::vector<double>& m, const char* name, State6* out) {
      if (m.empty()) return;
      if (m.size() != 225 && m.size() != 15)
        check(std::string("~") + name + " must be a 15x15 matrix (225 numbers) or its 15-entry diagonal, got " +
              std::to_string(m.size()) + " numbers");
      for (int i = 0; i < 15; ++i) {
        if (kPlanarIndex[i] < 0) continue;
        const double v = m.size() == 225 ? m[static_cast<std::size_t>(i) * 16] : m[static_cast<std::size_t>(i)];
        if (!(v > 0.0) || !std::isfinite(v))
          check(std::string("~") + name + ": diagonal entry for " + kConfigNames[i] + " must be > 0");
        (*out)(kPlanarIndex[i]) = v;
      }
    };
    s->process_noise << 0.05, 0.05, 0.06, 0.025, 0.025, 0.02;
    s->initial_covariance = State6::Constant(1e-9);
    diagonal(q, "process_noise_covariance", &s->process_noise);
    diagonal(p0, "initial_estimate_covariance", &s->initial_covariance);
  } catch (const thorvald_common::ParamError& e) {
    *error = e.what();
    return false;
  }
  return true;
}

class OdomFusionNode {
 public:
  OdomFusionNode(ros::NodeHandle& nh, ros::NodeHandle& pnh, const Settings& s) : s_(s), updater_(nh, pnh) {
    ekf_.setProcessNoise(s_.process_noise);
    ekf_.setInitialCovariance(s_.initial_covariance);
    odom_pub_ = nh.advertise<nav_msgs::Odometry>("odometry/filtered", 10);
    odom_sub_ = nh.subscribe(s_.odom0.topic, 20, &OdomFusionNode::onOdom, this);
    if (!s_.imu0.topic.empty()) imu_sub_ = nh.subscribe(s_.imu0.topic, 50, &OdomFusionNode::onImu, this);
    set_pose_sub_ = nh.subscribe("set_pose", 1, &OdomFusionNode::onSetPose, this);
    timer_ = nh.createTimer(ros::Duration(1.0 / s_.frequency), &OdomFusionNode::onTimer, this);
    updater_.setHardwareID("odom_fusion");
    updater_.add("fusion", this, &OdomFusionNode::diagnose);
  }

 private:
  bool advanceTo(const ros::Time& stamp) {
    const double t = stamp.toSec();
    if (!ekf_.initialized()) ekf_.reset(thorvald_base::Pose2D{}, t);
    if (t < ekf_.time()) {  // late measurement: fused at the filter's time (no history is kept)
      ++late_;
      return true;
    }
    return ekf_.predict(t);
  }

  void onOdom(const nav_msgs::Odometry::ConstPtr& msg) {
    const auto& tw = msg->twist.twist;
    State6 z = State6::Zero(), var = State6::Constant(1.0);
    z(kVx) = tw.linear.x;
    z(kVy) = tw.linear.y;
    z(kVyaw) = tw.angular.z;
    const auto& c = msg->twist.covariance;
    var(kVx) = std::max(s_.min_variance, c[0]);
    var(kVy) = std::max(s_.min_variance, c[7]);
    var(kVyaw) = std::max(s_.min_variance, c[35]);
    fuse(msg->header.stamp, z, var, s_.odom0.mask, s_.odom0_twist_gate, "odom0 twist");
    last_odom_ = ros::Time::now();
  }

  void onImu(const sensor_msgs::Imu::ConstPtr& msg) {
    State6 z = State6::Zero(), var = State6::Constant(1.0);
    std::array<bool, 6> mask = s_.imu0.mask;
    z(kVyaw) = msg->angular_velocity.z;  // flat-mounted IMU: its z axis is base_link's
    var(kVyaw) = std::max(s_.min_variance, msg->angular_velocity_covariance[8]);
    if (mask[kYaw]) {
      if (msg->orientation_covariance[0] < 0.0) {  // "no orientation" by sensor_msgs/Imu convention
        mask[kYaw] = false;
      } else {
        double yaw = thorvald_map::fromPose([&] {
                       geometry_msgs::Pose p;
                       p.orientation = msg->orientation;
                       return p;
                     }())
                         .yaw;
        if (s_.imu0.relative) {
          if (!have_yaw0_) {
            yaw0_ = yaw;
            have_yaw0_ = true;
          }
          yaw = thorvald_base::normalizeAngle(yaw - yaw0_);
        }
        z(kYaw) = yaw;
        var(kYaw) = std::max(s_.min_variance, msg->orientation_covariance[8]);
      }
    }
    // Yaw and yaw rate each behind its own gate, as robot_localization gates an IMU's parts.
    std::array<bool, 6> yaw_mask{}, rate_mask{};
    yaw_mask[kYaw] = mask[kYaw];
    rate_mask[kVyaw] = mask[kVyaw];
    if (yaw_mask[kYaw]) fuse(msg->header.stamp, z, var, yaw_mask, s_.imu0_pose_gate, "imu0 yaw");
    if (rate_mask[kVyaw]) fuse(msg->header.stamp, z, var, rate_mask, s_.imu0_rate_gate, "imu0 yaw rate");
    last_imu_ = ros::Time::now();
  }

  void fuse(const ros::Time& stamp, const State6& z, const State6& var, const std::array<bool, 6>& mask,
            double gate_sigma, const char* name) {
    if (!advanceTo(stamp.isZero() ? ros::Time::now() : stamp)) return;
    const UpdateResult r = ekf_.update(z, var, mask, gate_sigma);
    if (r.gated) {
      ++gated_;
      ROS_WARN_STREAM_THROTTLE(5.0, "odom_fusion: " << name << " refused by its rejection threshold: " << r.mahalanobis
                                                    << " sigma from the prediction (" << gate_sigma << ")");
      return;
    }
    if (!r.fused()) {
      ++rejected_;
      ROS_WARN_STREAM_THROTTLE(5.0, "odom_fusion: " << name << " measurement rejected: " << r.error);
      return;
    }
    ++fused_;
  }

  void onSetPose(const geometry_msgs::PoseWithCovarianceStamped::ConstPtr& msg) {
    const thorvald_base::Pose2D p = thorvald_map::fromPose(msg->pose.pose);
    if (!p.finite()) {
      ++rejected_;
      ROS_WARN("odom_fusion: set_pose with a non-finite pose ignored");
      return;
    }
    ekf_.reset(p, ros::Time::now().toSec());
    ROS_INFO_STREAM("odom_fusion: pose set to (" << p.x << ", " << p.y << ", " << p.yaw << ")");
  }

  void onTimer(const ros::TimerEvent&) {
    updater_.update();
    if (!ekf_.initialized()) return;
    const ros::Time now = ros::Time::now();
    ekf_.predict(now.toSec());
    nav_msgs::Odometry out;
    out.header.stamp = now;
    out.header.frame_id = s_.odom_frame;
    out.child_frame_id = s_.base_link_frame;
    out.pose.pose = thorvald_map::toPose(ekf_.pose());
    const State6& x = ekf_.state();
    const Cov6& p = ekf_.covariance();
    out.twist.twist.linear.x = x(kVx);
    out.twist.twist.linear.y = x(kVy);
    out.twist.twist.angular.z = x(kVyaw);
    const int pose_idx[3] = {0, 1, 5}, twist_idx[3] = {0, 1, 5};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        out.pose.covariance[pose_idx[i] * 6 + pose_idx[j]] = p(i, j);
        out.twist.covariance[twist_idx[i] * 6 + twist_idx[j]] = p(3 + i, 3 + j);
      }
    for (int k : {2, 3, 4}) out.pose.covariance[k * 7] = out.twist.covariance[k * 7] = 1e-9;  // planar
    odom_pub_.publish(out);
    if (s_.publish_tf) {
      geometry_msgs::TransformStamped t;
      t.header = out.header;
      t.child_frame_id = s_.base_link_frame;
      t.transform = thorvald_map::toTransform(ekf_.pose());
      tf_.sendTransform(t);
    }
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& st) {
    const ros::Time now = ros::Time::now();
    const bool odom_stale = last_odom_.isZero() || (now - last_odom_).toSec() > 10.0 * s_.sensor_timeout;
    const bool imu_stale =
        !s_.imu0.topic.empty() && (last_imu_.isZero() || (now - last_imu_).toSec() > 10.0 * s_.sensor_timeout);
    if (odom_stale) {
      st.summary(diagnostic_msgs::DiagnosticStatus::ERROR, "no wheel odometry on " + s_.odom0.topic);
    } else if (imu_stale && !s_.odom0.mask[kVyaw]) {
      // The IMU is the only source of the heading (odom0_config leaves the wheels' yaw rate out).
      st.summary(diagnostic_msgs::DiagnosticStatus::ERROR,
                 "no IMU on " + s_.imu0.topic + ": no yaw rate fused, the heading does not follow the robot's turns");
    } else if (imu_stale) {
      st.summary(diagnostic_msgs::DiagnosticStatus::WARN, "no IMU on " + s_.imu0.topic + ": wheel odometry only");
    } else {
      st.summary(diagnostic_msgs::DiagnosticStatus::OK, "fusing");
    }
    st.add("fused measurements", fused_);
    st.add("rejected measurements", rejected_);
    st.add("measurements over their rejection threshold", gated_);
    st.add("late measurements", late_);
  }

  Settings s_;
  PlanarEkf ekf_;
  diagnostic_updater::Updater updater_;
  ros::Publisher odom_pub_;
  ros::Subscriber odom_sub_, imu_sub_, set_pose_sub_;
  ros::Timer timer_;
  tf2_ros::TransformBroadcaster tf_;
  ros::Time last_odom_, last_imu_;
  bool have_yaw0_ = false;
  double yaw0_ = 0.0;
  long fused_ = 0, rejected_ = 0, gated_ = 0, late_ = 0;
};

}  // namespace
}  // namespace thorvald_navigation

int main(int argc, char** argv) {
  ros::init(argc, argv, "odom_fusion");
  ros::NodeHandle nh, pnh("~");
  thorvald_navigation::Settings settings;
  std::string error;
  if (!thorvald_navigation::loadSettings(pnh, &settings, &error)) {
    ROS_FATAL_STREAM(error);
    return 1;
  }
  thorvald_navigation::OdomFusionNode node(nh, pnh, settings);
  ros::spin();
  return 0;
}
