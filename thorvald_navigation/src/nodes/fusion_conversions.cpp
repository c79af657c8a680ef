#include "fusion_conversions.h"

namespace thorvald_navigation {

namespace {

Eigen::Quaterniond toEigen(const geometry_msgs::Quaternion& q) {
  const Eigen::Quaterniond e(q.w, q.x, q.y, q.z);
  return e.norm() > 1e-9 ? e.normalized() : Eigen::Quaterniond::Identity();
}

Eigen::Matrix3d matrix3(const boost::array<double, 9>& c) {
  Eigen::Matrix3d m;
  for (int i = 0; i < 9; ++i) m(i / 3, i % 3) = c[static_cast<std::size_t>(i)];
  return m;
}

Matrix6 matrix6(const boost::array<double, 36>& c) {
  Matrix6 m;
  for (int i = 0; i < 36; ++i) m(i / 6, i % 6) = c[static_cast<std::size_t>(i)];
  return m;
}

}  // namespace

Eigen::Isometry3d toIsometry(const geometry_msgs::Transform& t) {
  Eigen::Isometry3d e = Eigen::Isometry3d::Identity();
  e.translate(Eigen::Vector3d(t.translation.x, t.translation.y, t.translation.z));
  e.rotate(toEigen(t.rotation));
  return e;
}

PoseSample toPoseSample(const geometry_msgs::PoseWithCovariance& p) {
  PoseSample s;
  s.position = {p.pose.position.x, p.pose.position.y, p.pose.position.z};
  s.orientation = toEigen(p.pose.orientation);
  s.covariance = matrix6(p.covariance);
  return s;
}

TwistSample toTwistSample(const geometry_msgs::TwistWithCovariance& t) {
  TwistSample s;
  s.linear = {t.twist.linear.x, t.twist.linear.y, t.twist.linear.z};
  s.angular = {t.twist.angular.x, t.twist.angular.y, t.twist.angular.z};
  s.covariance = matrix6(t.covariance);
  return s;
}

ImuSample toImuSample(const sensor_msgs::Imu& m) {
  ImuSample s;
  s.orientation = toEigen(m.orientation);
  s.orientation_covariance = matrix3(m.orientation_covariance);
  s.angular_velocity = {m.angular_velocity.x, m.angular_velocity.y, m.angular_velocity.z};
  s.angular_velocity_covariance = matrix3(m.angular_velocity_covariance);
  s.linear_acceleration = {m.linear_acceleration.x, m.linear_acceleration.y, m.linear_acceleration.z};
  s.linear_acceleration_covariance = matrix3(m.linear_acceleration_covariance);
  return s;
}

nav_msgs::Odometry toOdometry(const FusionEkf& ekf, const ros::Time& stamp, const std::string& world_frame,
                              const std::string& base_link_frame) {
  const State15& x = ekf.state();
  const Cov15& p = ekf.covariance();
  nav_msgs::Odometry out;
  out.header.stamp = stamp;
  out.header.frame_id = world_frame;
  out.child_frame_id = base_link_frame;
  out.pose.pose.position.x = x(kFx);
  out.pose.pose.position.y = x(kFy);
  out.pose.pose.position.z = x(kFz);
  const Eigen::Quaterniond q = fromRollPitchYaw(x(kFroll), x(kFpitch), x(kFyaw));
  out.pose.pose.orientation.w = q.w();
  out.pose.pose.orientation.x = q.x();
  out.pose.pose.orientation.y = q.y();
  out.pose.pose.orientation.z = q.z();
  out.twist.twist.linear.x = x(kFvx);
  out.twist.twist.linear.y = x(kFvy);
  out.twist.twist.linear.z = x(kFvz);
  out.twist.twist.angular.x = x(kFvroll);
  out.twist.twist.angular.y = x(kFvpitch);
  out.twist.twist.angular.z = x(kFvyaw);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) {
      out.pose.covariance[static_cast<std::size_t>(i * 6 + j)] = p(i, j);
      out.twist.covariance[static_cast<std::size_t>(i * 6 + j)] = p(6 + i, 6 + j);
    }
  return out;
}

geometry_msgs::TransformStamped composeMapToOdom(const geometry_msgs::TransformStamped& map_base,
                                                 const geometry_msgs::TransformStamped& odom_base,
                                                 const std::string& odom_frame) {
  const Eigen::Isometry3d m = toIsometry(map_base.transform) * toIsometry(odom_base.transform).inverse();
  geometry_msgs::TransformStamped t;
  t.header = map_base.header;
  t.child_frame_id = odom_frame;
  t.transform.translation.x = m.translation().x();
  t.transform.translation.y = m.translation().y();
  t.transform.translation.z = m.translation().z();
  const Eigen::Quaterniond q(m.rotation());
  t.transform.rotation.w = q.w();
  t.transform.rotation.x = q.x();
  t.transform.rotation.y = q.y();
  t.transform.rotation.z = q.z();
  return t;
}

}  // namespace thorvald_navigation
