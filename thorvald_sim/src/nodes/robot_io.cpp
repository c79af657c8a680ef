#include "robot_io.h"

#include <geometry_msgs/TransformStamped.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <sensor_msgs/Range.h>
#include <sensor_msgs/point_cloud2_iterator.h>

#include <algorithm>
#include <cmath>
#include <thread>

#include "thorvald_sim/scene.h"

namespace thorvald_sim {

namespace {

geometry_msgs::Quaternion toMsg(const Eigen::Quaterniond& q) {
  geometry_msgs::Quaternion m;
  m.w = q.w(), m.x = q.x(), m.y = q.y(), m.z = q.z();
  return m;
}

// Optical frame (z forward, x right, y down) in a camera frame (x forward, z up).
Eigen::Matrix3d opticalInCamera() {
  Eigen::Matrix3d r;
  r << 0, 0, 1, -1, 0, 0, 0, -1, 0;
  return r;
}

sensor_msgs::CameraInfo cameraInfo(const DepthCameraSpec& s, const std::string& frame, const ros::Time& t) {
  const Intrinsics k = intrinsics(s);
  sensor_msgs::CameraInfo info;
  info.header.stamp = t;
  info.header.frame_id = frame;
  info.width = s.width, info.height = s.height;
  info.distortion_model = "plumb_bob";
  info.D.assign(5, 0.0);
  info.K = {k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1};
  info.R = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  info.P = {k.fx, 0, k.cx, 0, 0, k.fy, k.cy, 0, 0, 0, 1, 0};
  return info;
}

}  // namespace

RobotIo::RobotIo(ros::NodeHandle nh, Simulation& sim, size_t index, const std::string& tf_prefix,
                 std::vector<SensorConfig> sensors, const std::string& world_frame, bool publish_map_tf,
                 std::function<CameraRenderer&()> renderer, bool physics_encoders)
    : nh_(nh),
      sim_(sim),
      index_(index),
      name_(sim.robot(index).name),
      prefix_(tf_prefix),
      world_frame_(world_frame),
      publish_map_tf_(publish_map_tf),
      physics_encoders_(physics_encoders),
      renderer_(std::move(renderer)) {
  const mjModel* m = sim.model();
  for (int a = 0; a < m->nu; ++a) {
    const int j = m->actuator_trnid[2 * a];
    const char* jn = mj_id2name(m, mjOBJ_JOINT, j);
    if (!jn || m->jnt_bodyid[j] < 0 || m->body_rootid[m->jnt_bodyid[j]] != sim.robot(index).root_body) continue;
    std::string n(jn);
    const auto slash = n.rfind('/');
    actuators_[n] = {a, jointRole(slash == std::string::npos ? n : n.substr(slash + 1)) == JointRole::kSteering};
  }
  if (physics_encoders_) {
    // base_driver's joint_states are then the measurements themselves: targets come from SimHardware.
    joint_sub_ = nh_.subscribe("sim/joint_commands", 50, &RobotIo::onJointStates, this);
    measured_pub_ = nh_.advertise<sensor_msgs::JointState>("sim/joint_measured", 10);
    for (const auto& a : actuators_) measured_joints_.push_back(a.first);
  } else {
    joint_sub_ = nh_.subscribe("joint_states", 20, &RobotIo::onJointStates, this);
  }
  if (publish_map_tf_) odom_sub_ = nh_.subscribe("odometry/base_raw", 20, &RobotIo::onOdometry, this);
  truth_pub_ = nh_.advertise<nav_msgs::Odometry>("ground_truth/odom", 10);
  std::vector<geometry_msgs::TransformStamped> mounts;
  for (auto& c : sensors) {
    Sensor s;
    s.config = c;
    s.frame = frame(c.name);
    s.parent_body = mj_name2id(m, mjOBJ_BODY, frame(c.parent).c_str());
    if (s.parent_body < 0) throw ModelError("sensor " + c.name + ": no link " + frame(c.parent) + " in the model");
    s.mount = c.mountRotation();
    s.rng.seed(c.seed + 7919u * static_cast<unsigned>(index));
    if (c.type == SensorType::kImu && c.imu.realism == Realism::kDatasheet)
      s.imu_errors = std::make_unique<ImuErrors>(c.imu.model, s.rng);
    geometry_msgs::TransformStamped t;
    t.header.frame_id = frame(c.parent);
    t.child_frame_id = s.frame;
    t.transform.translation.x = c.xyz.x(), t.transform.translation.y = c.xyz.y(), t.transform.translation.z = c.xyz.z();
    t.transform.rotation = toMsg(Eigen::Quaterniond(s.mount));
    mounts.push_back(t);
    switch (c.type) {
      case SensorType::kLidar:
        s.pub = nh_.advertise<sensor_msgs::LaserScan>(c.topic, 5);
        break;
      case SensorType::kUltrasonic:
        s.pub = nh_.advertise<sensor_msgs::Range>(c.topic, 5);
        break;
      case SensorType::kImu:
        s.pub = nh_.advertise<sensor_msgs::Imu>(c.topic, 20);
        break;
      case SensorType::kDepthCamera: {
        s.pub = nh_.advertise<sensor_msgs::PointCloud2>(c.topic + "/depth/points", 2);
        s.info_pub = nh_.advertise<sensor_msgs::CameraInfo>(c.topic + "/depth/camera_info", 2);
        if (c.color) {
          s.color_pub = nh_.advertise<sensor_msgs::Image>(c.topic + "/color/image_raw", 2);
          s.color_info_pub = nh_.advertise<sensor_msgs::CameraInfo>(c.topic + "/color/camera_info", 2);
        }
        geometry_msgs::TransformStamped o;
        o.header.frame_id = s.frame;
        o.child_frame_id = s.frame + "_optical";
        o.transform.rotation = toMsg(Eigen::Quaterniond(opticalInCamera()));
        mounts.push_back(o);
        break;
      }
    }
    sensors_.push_back(std::move(s));
  }
  if (!mounts.empty()) static_tf_.sendTransform(mounts);
}

void RobotIo::onJointStates(const sensor_msgs::JointState::ConstPtr& msg) {
  ++joint_msgs_;
  for (size_t i = 0; i < msg->name.size(); ++i) {
    const auto it = actuators_.find(msg->name[i]);
    if (it == actuators_.end()) {
      ++unknown_joints_;
      continue;
    }
    const auto& values = it->second.second ? msg->position : msg->velocity;
    if (i >= values.size() || !sim_.setTarget(it->second.first, values[i])) ++rejected_values_;
  }
}

void RobotIo::onOdometry(const nav_msgs::Odometry::ConstPtr& msg) {
  // map -> odom = (map -> base_link, the truth) * (odom -> base_link)^-1: a perfect localiser.
  const auto& p = msg->pose.pose;
  const Eigen::Quaterniond q(p.orientation.w, p.orientation.x, p.orientation.y, p.orientation.z);
  if (!std::isfinite(p.position.x) || !std::isfinite(p.position.y) || q.norm() < 0.5) {
    ++rejected_values_;
    return;
  }
  const Eigen::Isometry3d odom_base = Eigen::Translation3d(p.position.x, p.position.y, p.position.z) * q.normalized();
  const BodyState b = sim_.robotState(index_);
  const Eigen::Isometry3d map_base = Eigen::Translation3d(b.position) * b.orientation;
  const Eigen::Isometry3d map_odom = map_base * odom_base.inverse();
  geometry_msgs::TransformStamped t;
  t.header.stamp = msg->header.stamp;
  t.header.frame_id = world_frame_;
  t.child_frame_id = frame("odom");
  t.transform.translation.x = map_odom.translation().x();
  t.transform.translation.y = map_odom.translation().y();
  t.transform.translation.z = map_odom.translation().z();
  t.transform.rotation = toMsg(Eigen::Quaterniond(map_odom.rotation()));
  tf_.sendTransform(t);
}

void RobotIo::restart() {
  next_truth_s_ = 0.0;
  for (auto& s : sensors_) s.next_s = 0.0;
}

void RobotIo::publish(const ros::Time& now, double ground_truth_period_s) {
  const double t = now.toSec();
  if (physics_encoders_) {
    sensor_msgs::JointState js;
    js.header.stamp = now;
    for (const auto& j : measured_joints_) {
      double p = 0.0, v = 0.0;
      if (!sim_.jointState(j, &p, &v)) continue;
      js.name.push_back(j);
      js.position.push_back(p);
      js.velocity.push_back(v);
    }
    measured_pub_.publish(js);
  }
  if (t + 1e-9 >= next_truth_s_) {
    next_truth_s_ = t + ground_truth_period_s;
    const BodyState b = sim_.robotState(index_);
    nav_msgs::Odometry o;
    o.header.stamp = now;
    o.header.frame_id = world_frame_;
    o.child_frame_id = frame("base_link");
    o.pose.pose.position.x = b.position.x(), o.pose.pose.position.y = b.position.y();
    o.pose.pose.position.z = b.position.z();
    o.pose.pose.orientation = toMsg(b.orientation);
    o.twist.twist.linear.x = b.linear_body.x(), o.twist.twist.linear.y = b.linear_body.y();
    o.twist.twist.linear.z = b.linear_body.z();
    o.twist.twist.angular.x = b.angular_body.x(), o.twist.twist.angular.y = b.angular_body.y();
    o.twist.twist.angular.z = b.angular_body.z();
    truth_pub_.publish(o);
  }
  bool accelerations = false;
  for (auto& s : sensors_) {
    if (t + 1e-9 < s.next_s) continue;
    s.next_s = std::max(s.next_s + 1.0 / s.config.rate_hz, t);
    if (s.config.type == SensorType::kImu && !accelerations) {
      sim_.updateAccelerations();
      accelerations = true;
    }
    publishSensor(s, now);
  }
}

void RobotIo::publishSensor(Sensor& s, const ros::Time& now) {
  Eigen::Vector3d bp;
  Eigen::Quaterniond bq;
  const char* body = mj_id2name(sim_.model(), mjOBJ_BODY, s.parent_body);
  sim_.bodyPose(body, &bp, &bq);
  SensorPose pose;
  pose.origin = bp + bq * s.config.xyz;
  pose.rotation = bq.toRotationMatrix() * s.mount;
  RayCaster caster(sim_.model(), sim_.data(), sim_.robot(index_).root_body);
  const auto& c = s.config;
  switch (c.type) {
    case SensorType::kLidar: {
      if (s.pub.getNumSubscribers() == 0) return;
      sensor_msgs::LaserScan m;
      m.header.stamp = now;
      m.header.frame_id = s.frame;
      m.angle_min = c.lidar.angle_min_rad, m.angle_max = c.lidar.angle_max_rad;
      m.angle_increment = c.lidar.samples > 1 ? (m.angle_max - m.angle_min) / (c.lidar.samples - 1) : 0.0;
      m.scan_time = 1.0 / c.rate_hz;
      m.range_min = c.lidar.range_min_m, m.range_max = c.lidar.range_max_m;
      const SensorPose sweep_end = sweepEnd(sim_.model(), sim_.data(), s.parent_body, pose, c.lidar.model.sweep_s);
      m.ranges =
          simulateLidar(caster, pose, c.lidar, s.rng, c.lidar.realism == Realism::kDatasheet ? &sweep_end : nullptr);
      s.pub.publish(m);
      break;
    }
    case SensorType::kUltrasonic: {
      sensor_msgs::Range m;
      m.header.stamp = now;
      m.header.frame_id = s.frame;
      m.radiation_type = sensor_msgs::Range::ULTRASOUND;
      m.field_of_view = c.ultrasonic.fov_rad;
      m.min_range = c.ultrasonic.range_min_m, m.max_range = c.ultrasonic.range_max_m;
      m.range = simulateUltrasonic(caster, pose, c.ultrasonic, s.rng);
      s.pub.publish(m);
      break;
    }
    case SensorType::kImu: {
      const ImuReading r =
          simulateImu(sim_.model(), sim_.data(), s.parent_body, s.mount, c.imu, s.rng, s.imu_errors.get(), now.toSec());
      sensor_msgs::Imu m;
      m.header.stamp = now;
      m.header.frame_id = s.frame;
      m.orientation = toMsg(r.orientation);
      m.angular_velocity.x = r.angular_velocity.x(), m.angular_velocity.y = r.angular_velocity.y();
      m.angular_velocity.z = r.angular_velocity.z();
      m.linear_acceleration.x = r.linear_acceleration.x(), m.linear_acceleration.y = r.linear_acceleration.y();
      m.linear_acceleration.z = r.linear_acceleration.z();
      const bool datasheet = c.imu.realism == Realism::kDatasheet;
      const double gyro_sd = datasheet ? c.imu.model.gyro.white_sigma : c.imu.gyro_noise_radps;
      const double accel_sd = datasheet ? c.imu.model.accel.white_sigma : c.imu.accel_noise_mps2;
      for (int i = 0; i < 3; ++i) {
        m.angular_velocity_covariance[4 * i] = gyro_sd * gyro_sd;
        m.linear_acceleration_covariance[4 * i] = accel_sd * accel_sd;
        m.orientation_covariance[4 * i] = 1e-6;
      }
      s.pub.publish(m);
      break;
    }
    case SensorType::kDepthCamera:
      publishCamera(s, pose, now);
      break;
  }
}

void RobotIo::publishCamera(Sensor& s, const SensorPose& pose, const ros::Time& now) {
  const auto& c = s.config;
  const std::string oframe = s.frame + "_optical";
  s.info_pub.publish(cameraInfo(c.depth, oframe, now));
  const bool depth = s.pub.getNumSubscribers() > 0;
  const bool color = c.color && s.color_pub.getNumSubscribers() > 0;
  if (!depth && !color) return;  // a camera nobody watches costs nothing
  SensorPose optical = pose;
  optical.rotation = pose.rotation * opticalInCamera();
  ColorCameraSpec cs;
  cs.width = c.depth.width, cs.height = c.depth.height, cs.hfov_rad = c.depth.hfov_rad;
  cs.focal_px = c.depth.focal_px, cs.cx_px = c.depth.cx_px, cs.cy_px = c.depth.cy_px;
  const int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  try {
    renderer_().render(sim_.data(), optical, cameraView(c.depth, color, cs.range_max_m), sim_.robot(index_).root_body,
                       &view_, threads);
  } catch (const RenderError& e) {
    ++camera_errors_;
    ROS_ERROR_THROTTLE(5.0, "thorvald_sim: camera %s: %s", s.frame.c_str(), e.what());
    return;
  }
  ++camera_frames_;
  if (depth) {
    const RayCaster normals(sim_.model(), sim_.data(), sim_.robot(index_).root_body);
    depthFromView(view_, normals, optical, c.depth, s.rng, &depth_img_, threads);
    const DepthImage& img = depth_img_;
    sensor_msgs::PointCloud2 cloud;
    cloud.header.stamp = now;
    cloud.header.frame_id = oframe;
    sensor_msgs::PointCloud2Modifier mod(cloud);
    mod.setPointCloud2FieldsByString(1, "xyz");
    mod.resize(static_cast<size_t>(img.width) * img.height);
    cloud.height = img.height, cloud.width = img.width;
    cloud.row_step = cloud.point_step * cloud.width;
    cloud.is_dense = false;
    sensor_msgs::PointCloud2Iterator<float> x(cloud, "x"), y(cloud, "y"), z(cloud, "z");
    for (const auto& p : img.points) *x = p.x(), *y = p.y(), *z = p.z(), ++x, ++y, ++z;
    s.pub.publish(cloud);
  }
  if (color) {
    colorFromView(view_, sim_.model(), cs, &color_img_);
    const ColorImage& img = color_img_;
    sensor_msgs::Image m;
    m.header.stamp = now;
    m.header.frame_id = oframe;
    m.width = img.width, m.height = img.height;
    m.encoding = "rgb8";
    m.step = 3 * img.width;
    m.data = img.rgb;
    s.color_pub.publish(m);
    s.color_info_pub.publish(cameraInfo(c.depth, oframe, now));
  }
}

void RobotIo::diagnostics(diagnostic_updater::DiagnosticStatusWrapper& stat) const {
  const std::string who = name_.empty() ? "robot" : name_;
  stat.add(who + " encoders", physics_encoders_ ? "physics (SimHardware)" : "base_driver's joint simulator");
  stat.add(who + " joint targets received", joint_msgs_);
  stat.add(who + " rejected values", rejected_values_);
  stat.add(who + " joints without actuator", unknown_joints_);
  stat.add(who + " sensors", sensors_.size());
  stat.add(who + " camera frames rendered", camera_frames_);
  stat.add(who + " camera errors", camera_errors_);
}

}  // namespace thorvald_sim
