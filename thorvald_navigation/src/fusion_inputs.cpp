#include "thorvald_navigation/fusion_inputs.h"

#include <algorithm>
#include <cmath>

namespace thorvald_navigation {

Eigen::Vector3d rollPitchYaw(const Eigen::Quaterniond& q) {
  const Eigen::Matrix3d r = q.normalized().toRotationMatrix();
  const double pitch = std::asin(std::clamp(-r(2, 0), -1.0, 1.0));
  const double roll = std::atan2(r(2, 1), r(2, 2));
  const double yaw = std::atan2(r(1, 0), r(0, 0));
  return {roll, pitch, yaw};
}

Eigen::Quaterniond fromRollPitchYaw(double roll, double pitch, double yaw) {
  return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
         Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX());
}

double InputConverter::var(double v) const { return std::isfinite(v) ? std::max(min_variance_, v) : v; }

std::vector<Measurement> InputConverter::poseEntries(const Eigen::Isometry3d& pose_in, const Matrix6& cov, int first,
                                                     double t) {
  std::vector<Measurement> out;
  Eigen::Isometry3d pose = pose_in;
  if (c_.relative) {
    if (!first_pose_) first_pose_ = pose_in;
    pose = first_pose_->inverse() * pose_in;
  }
  if (c_.differential) {
    const bool have_previous = previous_pose_.has_value();
    const Eigen::Isometry3d previous = have_previous ? *previous_pose_ : pose;
    const Matrix6 previous_cov = previous_cov_;
    const double dt = t - previous_t_;
    previous_pose_ = pose;
    previous_cov_ = cov;
    previous_t_ = t;
    if (!have_previous || !(dt > 0.0)) return out;
    // The motion between the two messages in the earlier pose's frame, as body velocities.
    const Eigen::Isometry3d delta = previous.inverse() * pose;
    Eigen::Matrix<double, 6, 1> rate;
    rate.head<3>() = delta.translation() / dt;
    rate.tail<3>() = rollPitchYaw(Eigen::Quaterniond(delta.rotation())) / dt;
    Measurement m;
    m.part = "pose (differential)";
    m.gate_sigma = c_.pose_gate;
    for (int i = first; i < 6; ++i)
      if (c_.use[i]) m.entries.push_back({i + 6, rate(i), var((cov(i, i) + previous_cov(i, i)) / (dt * dt))});
    if (!m.entries.empty()) out.push_back(m);
    return out;
  }
  Eigen::Matrix<double, 6, 1> z;
  z.head<3>() = pose.translation();
  z.tail<3>() = rollPitchYaw(Eigen::Quaterniond(pose.rotation()));
  Measurement m;
  m.part = first < 3 ? "pose" : "orientation";
  m.gate_sigma = c_.pose_gate;
  for (int i = first; i < 6; ++i)
    if (c_.use[i]) m.entries.push_back({i, z(i), var(cov(i, i))});
  if (!m.entries.empty()) out.push_back(m);
  return out;
}

std::vector<Measurement> InputConverter::fromPose(const PoseSample& p, double t) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translate(p.position);
  pose.rotate(p.orientation.normalized());
  return poseEntries(pose, p.covariance, 0, t);
}

std::vector<Measurement> InputConverter::fromTwist(const TwistSample& tw) const {
  const Eigen::Matrix3d r = c_.mount.normalized().toRotationMatrix();
  Eigen::Matrix<double, 6, 1> z;
  z.head<3>() = r * tw.linear;
  z.tail<3>() = r * tw.angular;
  Measurement m;
  m.part = "twist";
  m.gate_sigma = c_.twist_gate;
  for (int i = 0; i < 6; ++i)
    if (c_.use[i + 6]) m.entries.push_back({i + 6, z(i), var(tw.covariance(i, i))});
  std::vector<Measurement> out;
  if (!m.entries.empty()) out.push_back(m);
  return out;
}

std::vector<Measurement> InputConverter::fromImu(const ImuSample& s, double t) {
  std::vector<Measurement> out;
  const Eigen::Quaterniond mount = c_.mount.normalized();
  const bool has_orientation = s.orientation_covariance(0, 0) >= 0.0;
  const Eigen::Quaterniond base_in_world = (s.orientation.normalized() * mount.inverse()).normalized();
  if (has_orientation && (c_.use[kFroll] || c_.use[kFpitch] || c_.use[kFyaw])) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.rotate(base_in_world);
    Matrix6 cov = Matrix6::Identity();
    const Eigen::Matrix3d r = mount.toRotationMatrix();
    cov.bottomRightCorner<3, 3>() = r * s.orientation_covariance * r.transpose();
    for (Measurement& m : poseEntries(pose, cov, 3, t)) out.push_back(m);
  }
  if (s.angular_velocity_covariance(0, 0) >= 0.0) {
    const Eigen::Matrix3d r = mount.toRotationMatrix();
    const Eigen::Vector3d w = r * s.angular_velocity;
    const Eigen::Matrix3d cov = r * s.angular_velocity_covariance * r.transpose();
    Measurement m;
    m.part = "angular velocity";
    m.gate_sigma = c_.angular_velocity_gate;
    for (int i = 0; i < 3; ++i)
      if (c_.use[kFvroll + i]) m.entries.push_back({kFvroll + i, w(i), var(cov(i, i))});
    if (!m.entries.empty()) out.push_back(m);
  }
  if (s.linear_acceleration_covariance(0, 0) >= 0.0) {
    const Eigen::Matrix3d r = mount.toRotationMatrix();
    Eigen::Vector3d a = r * s.linear_acceleration;
    // An accelerometer at rest reads +g upwards: take gravity out in base_link through the IMU's orientation.
    if (c_.remove_gravity) a -= base_in_world.inverse() * Eigen::Vector3d(0.0, 0.0, c_.gravity);
    const Eigen::Matrix3d cov = r * s.linear_acceleration_covariance * r.transpose();
    Measurement m;
    m.part = "linear acceleration";
    m.gate_sigma = c_.linear_acceleration_gate;
    for (int i = 0; i < 3; ++i)
      if (c_.use[kFax + i]) m.entries.push_back({kFax + i, a(i), var(cov(i, i))});
    if (!m.entries.empty()) out.push_back(m);
  }
  return out;
}

}  // namespace thorvald_navigation
