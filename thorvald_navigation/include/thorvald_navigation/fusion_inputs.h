#pragma once

#include <array>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "thorvald_navigation/fusion_ekf.h"

namespace thorvald_navigation {

using Matrix6 = Eigen::Matrix<double, 6, 6>;

/// A pose with its covariance (x y z roll pitch yaw order), as geometry_msgs/PoseWithCovariance carries it.
struct PoseSample {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< [m]
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  Matrix6 covariance = Matrix6::Identity();  ///< [m^2, rad^2]
};

/// A twist with its covariance (vx vy vz vroll vpitch vyaw order), in the sensor's frame.
struct TwistSample {
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();   ///< [m/s]
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();  ///< [rad/s]
  Matrix6 covariance = Matrix6::Identity();
};

/// An IMU reading in the IMU's frame, as sensor_msgs/Imu carries it; a covariance whose first entry is -1 marks
/// the part as absent (sensor_msgs/Imu's convention).
struct ImuSample {
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  Eigen::Matrix3d orientation_covariance = Eigen::Matrix3d::Identity();
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();
  Eigen::Matrix3d angular_velocity_covariance = Eigen::Matrix3d::Identity();
  Eigen::Vector3d linear_acceleration = Eigen::Vector3d::Zero();
  Eigen::Matrix3d linear_acceleration_covariance = Eigen::Matrix3d::Identity();
};

/// One input's robot_localization settings (odomN, imuN, poseN, twistN and their suffixed keys).
struct InputConfig {
  std::array<bool, 15> use{};   ///< *_config: x y z roll pitch yaw vx vy vz vroll vpitch vyaw ax ay az
  bool differential = false;    ///< pose entries fused as the velocity between two messages
  bool relative = false;        ///< pose entries relative to the first message
  bool remove_gravity = false;  ///< IMU: subtract gravity from the linear acceleration
  double gravity = 9.80665;     ///< [m/s^2]
  double pose_gate = std::numeric_limits<double>::infinity();  ///< Mahalanobis gates [sigma]
  double twist_gate = std::numeric_limits<double>::infinity();
  double angular_velocity_gate = std::numeric_limits<double>::infinity();
  double linear_acceleration_gate = std::numeric_limits<double>::infinity();
  /// The sensor frame's rotation in base_link (IMU mounting; identity when the sensor reports in base_link).
  Eigen::Quaterniond mount = Eigen::Quaterniond::Identity();
};

/// One group of entries to fuse together, with its gate and which part of the message it came from.
struct Measurement {
  std::vector<MeasuredEntry> entries;
  double gate_sigma = std::numeric_limits<double>::infinity();
  std::string part;  ///< "pose", "twist", "orientation", "angular velocity", "linear acceleration"
};

/// Turns one input's messages into the filter's measurements as robot_localization does: the *_config entries
/// selected, the IMU rotated from its mounting into base_link (gravity removed if asked), a relative input taken
/// against its first message, a differential one turned into velocities between consecutive messages
/// (variance: the two poses' variances summed over dt^2). Uses the covariances' diagonals, floored at
/// `min_variance`. ROS-free; one converter per input, it keeps the input's first and previous pose.
class InputConverter {
 public:
  explicit InputConverter(const InputConfig& config, double min_variance = 1e-9)
      : c_(config), min_variance_(min_variance) {}

  std::vector<Measurement> fromPose(const PoseSample& pose, double t);
  std::vector<Measurement> fromTwist(const TwistSample& twist) const;
  std::vector<Measurement> fromImu(const ImuSample& imu, double t);
  const InputConfig& config() const { return c_; }

 private:
  std::vector<Measurement> poseEntries(const Eigen::Isometry3d& pose, const Matrix6& cov, int first, double t);
  double var(double v) const;

  InputConfig c_;
  double min_variance_;
  std::optional<Eigen::Isometry3d> first_pose_, previous_pose_;
  Matrix6 previous_cov_ = Matrix6::Identity();
  double previous_t_ = 0.0;
};

/// Roll, pitch, yaw [rad] of a rotation (z-y-x order, as tf2's getRPY).
Eigen::Vector3d rollPitchYaw(const Eigen::Quaterniond& q);
/// The rotation of roll, pitch, yaw [rad].
Eigen::Quaterniond fromRollPitchYaw(double roll, double pitch, double yaw);

}  // namespace thorvald_navigation
