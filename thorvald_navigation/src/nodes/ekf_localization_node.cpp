// ekf_localization: the 15-state EKF with robot_localization's parameters and topics (odomN, imuN, poseN, twistN,
// *_config, two_d_mode, world_frame), publishing odometry/filtered, the world frame's transform, diagnostics and
// localization_ok. Thin shell around FusionEkf, InputConverter and FusionMonitor.
#include <memory>
#include <string>
#include <vector>

#include <diagnostic_updater/diagnostic_updater.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/TwistWithCovarianceStamped.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>
#include <std_msgs/Bool.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>
#include <thorvald_common/ros/run_node.h>

#include "ekf_settings.h"
#include "fusion_conversions.h"
#include "thorvald_navigation/fusion_monitor.h"

namespace thorvald_navigation {
namespace {

class EkfLocalizationNode {
 public:
  EkfLocalizationNode(ros::NodeHandle& nh, ros::NodeHandle& pnh) : updater_(nh, pnh), tf_listener_(tf_buffer_) {
    thorvald_common::ParamReader reader(pnh, "ekf_localization");
    s_ = readEkfSettings(reader);
    reader.alsoRead("diagnostic_period");
    reader.finish();
    const std::string warning = unsupportedWarning(s_);
    if (!warning.empty()) ROS_WARN_STREAM("ekf_localization: " << warning);
    ekf_.setTwoDMode(s_.two_d_mode);
    ekf_.setProcessNoise(s_.process_noise);
    ekf_.setInitialCovariance(s_.initial_covariance);
    const double now = ros::Time::now().toSec();
    monitor_.setStart(now);
    for (const EkfInput& in : s_.inputs) {
      converters_.push_back(std::make_unique<InputConverter>(in.config));
      monitor_.addInput(in.name + " (" + in.topic + ")", in.status_timeout_s, true);
      subscribe(nh, in, converters_.size() - 1);
    }
    odom_pub_ = nh.advertise<nav_msgs::Odometry>("odometry/filtered", 10);
    ok_pub_ = nh.advertise<std_msgs::Bool>("localization_ok", 1, true);
    set_pose_sub_ = nh.subscribe("set_pose", 1, &EkfLocalizationNode::onSetPose, this);
    timer_ = nh.createTimer(ros::Duration(1.0 / s_.frequency), &EkfLocalizationNode::onTimer, this);
    updater_.setHardwareID("ekf_localization");
    updater_.add("fusion", this, &EkfLocalizationNode::diagnose);
  }

 private:
  std::string label(std::size_t i) const { return s_.inputs[i].name + " (" + s_.inputs[i].topic + ")"; }

  void subscribe(ros::NodeHandle& nh, const EkfInput& in, std::size_t i) {
    const uint32_t q = static_cast<uint32_t>(in.queue_size);
    switch (in.kind) {
      case EkfInput::kOdom:
        subs_.push_back(nh.subscribe<nav_msgs::Odometry>(in.topic, q, [this, i](const nav_msgs::OdometryConstPtr& m) {
          if (!inWorldFrame(i, m->header.frame_id)) return;
          if (!mount(i, m->child_frame_id)) return;
          const double t = stampOf(m->header);
          std::vector<Measurement> z = converters_[i]->fromPose(toPoseSample(m->pose), t);
          for (const Measurement& tw : converters_[i]->fromTwist(toTwistSample(m->twist))) z.push_back(tw);
          fuse(i, t, z);
        }));
        break;
      case EkfInput::kImu:
        subs_.push_back(nh.subscribe<sensor_msgs::Imu>(in.topic, q, [this, i](const sensor_msgs::ImuConstPtr& m) {
          if (!mount(i, m->header.frame_id)) return;
          const double t = stampOf(m->header);
          fuse(i, t, converters_[i]->fromImu(toImuSample(*m), t));
        }));
        break;
      case EkfInput::kPose:
        subs_.push_back(nh.subscribe<geometry_msgs::PoseWithCovarianceStamped>(
            in.topic, q, [this, i](const geometry_msgs::PoseWithCovarianceStampedConstPtr& m) {
              if (!inWorldFrame(i, m->header.frame_id)) return;
              const double t = stampOf(m->header);
              fuse(i, t, converters_[i]->fromPose(toPoseSample(m->pose), t));
            }));
        break;
      case EkfInput::kTwist:
        subs_.push_back(nh.subscribe<geometry_msgs::TwistWithCovarianceStamped>(
            in.topic, q, [this, i](const geometry_msgs::TwistWithCovarianceStampedConstPtr& m) {
              if (!mount(i, m->header.frame_id)) return;
              fuse(i, stampOf(m->header), converters_[i]->fromTwist(toTwistSample(m->twist)));
            }));
        break;
    }
  }

  double stampOf(const std_msgs::Header& h) const { return (h.stamp.isZero() ? ros::Time::now() : h.stamp).toSec(); }

  /// Pose data must be in the world frame (no transform of pose sources between frames).
  bool inWorldFrame(std::size_t i, const std::string& frame) {
    const InputConfig& c = converters_[i]->config();
    bool uses_pose = false;
    for (int k = 0; k < 6; ++k) uses_pose = uses_pose || c.use[k];
    if (!uses_pose || frame.empty() || frame == s_.world_frame || c.differential || c.relative) return true;
    refuse(i, "pose in frame '" + frame + "', expected the world frame '" + s_.world_frame + "'");
    return false;
  }

  /// Rotation of a sensor frame in base_link from tf, looked up once per input.
  bool mount(std::size_t i, const std::string& frame) {
    if (frame.empty() || frame == s_.base_link_frame) return true;
    if (mounted_.size() <= i) mounted_.resize(s_.inputs.size(), false);
    if (mounted_[i]) return true;
    try {
      const auto t = tf_buffer_.lookupTransform(s_.base_link_frame, frame, ros::Time(0));
      const auto& q = t.transform.rotation;
      InputConfig c = converters_[i]->config();
      c.mount = Eigen::Quaterniond(q.w, q.x, q.y, q.z);
      *converters_[i] = InputConverter(c);
      mounted_[i] = true;
      return true;
    } catch (const tf2::TransformException& e) {
      refuse(i, "no transform from '" + frame + "' to '" + s_.base_link_frame + "': " + e.what());
      return false;
    }
  }

  void refuse(std::size_t i, const std::string& why) {
    ++rejected_;
    monitor_.received(label(i), ros::Time::now().toSec());
    monitor_.refused(label(i), why);
    ROS_WARN_STREAM_THROTTLE(5.0, "ekf_localization: " << label(i) << " refused: " << why);
  }

  void fuse(std::size_t i, double t, const std::vector<Measurement>& z) {
    monitor_.received(label(i), ros::Time::now().toSec());
    if (!ekf_.initialized()) ekf_.reset(s_.initial_state, t);
    if (t < ekf_.time())
      ++late_;  // fused at the filter's time: no history is kept
    else
      ekf_.predict(t);
    for (const Measurement& m : z) {
      const UpdateResult r = ekf_.update(m.entries, m.gate_sigma);
      if (r.fused()) {
        ++fused_;
        monitor_.fused(label(i));
      } else {
        refuse(i, m.part + ": " + r.error);
      }
    }
  }

  void onSetPose(const geometry_msgs::PoseWithCovarianceStampedConstPtr& m) {
    const PoseSample p = toPoseSample(m->pose);
    const Eigen::Vector3d rpy = rollPitchYaw(p.orientation);
    if (!p.position.allFinite() || !rpy.allFinite()) {
      ++rejected_;
      ROS_WARN("ekf_localization: set_pose with a non-finite pose ignored");
      return;
    }
    State15 x = State15::Zero();
    x.head<3>() = p.position;
    x.segment<3>(kFroll) = rpy;
    ekf_.reset(x, ros::Time::now().toSec());
    ROS_INFO_STREAM("ekf_localization: pose set to (" << x(kFx) << ", " << x(kFy) << ", " << x(kFyaw) << ")");
  }

  void onTimer(const ros::TimerEvent&) {
    updater_.update();
    const ros::Time now = ros::Time::now();
    const FusionHealth h = monitor_.evaluate(now.toSec());
    std_msgs::Bool ok;
    ok.data = h.localization_ok && ekf_.initialized();
    ok_pub_.publish(ok);
    if (!ekf_.initialized()) return;
    if (now.toSec() > ekf_.time()) ekf_.predict(now.toSec());
    const nav_msgs::Odometry out = toOdometry(ekf_, now, s_.world_frame, s_.base_link_frame);
    odom_pub_.publish(out);
    if (s_.publish_tf) publishTf(out);
  }

  void publishTf(const nav_msgs::Odometry& out) {
    geometry_msgs::TransformStamped t;
    t.header = out.header;
    t.child_frame_id = s_.base_link_frame;
    t.transform.translation.x = out.pose.pose.position.x;
    t.transform.translation.y = out.pose.pose.position.y;
    t.transform.translation.z = out.pose.pose.position.z;
    t.transform.rotation = out.pose.pose.orientation;
    if (s_.world_frame == s_.map_frame) {
      // As robot_localization: map -> odom, so that map -> odom -> base_link gives the fused pose.
      try {
        const auto odom_base = tf_buffer_.lookupTransform(s_.odom_frame, s_.base_link_frame, ros::Time(0));
        t = composeMapToOdom(t, odom_base, s_.odom_frame);
      } catch (const tf2::TransformException& e) {
        ROS_WARN_STREAM_THROTTLE(5.0, "ekf_localization: no " << s_.odom_frame << " -> " << s_.base_link_frame
                                                              << " for map -> odom: " << e.what());
        return;
      }
    }
    tf_.sendTransform(t);
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& st) {
    const FusionHealth h = monitor_.evaluate(ros::Time::now().toSec());
    st.summary(static_cast<unsigned char>(h.level), h.summary());
    st.add("localization_ok", h.localization_ok && ekf_.initialized());
    st.add("fused measurements", fused_);
    st.add("rejected measurements", rejected_);
    st.add("late measurements", late_);
  }

  EkfSettings s_;
  FusionEkf ekf_;
  FusionMonitor monitor_;
  std::vector<std::unique_ptr<InputConverter>> converters_;
  std::vector<bool> mounted_;
  diagnostic_updater::Updater updater_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  tf2_ros::TransformBroadcaster tf_;
  std::vector<ros::Subscriber> subs_;
  ros::Subscriber set_pose_sub_;
  ros::Publisher odom_pub_, ok_pub_;
  ros::Timer timer_;
  long fused_ = 0, rejected_ = 0, late_ = 0;
};

}  // namespace
}  // namespace thorvald_navigation

int main(int argc, char** argv) {
  return thorvald_common::runNode<thorvald_navigation::EkfLocalizationNode>(argc, argv, "ekf_localization");
}
