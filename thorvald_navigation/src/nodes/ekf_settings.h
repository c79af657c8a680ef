// ekf_localization's parameters, read with robot_localization's names through the workspace's strict reader.
#pragma once

#include <string>
#include <vector>

#include <thorvald_common/ros/param_reader.h>

#include "thorvald_navigation/fusion_ekf.h"
#include "thorvald_navigation/fusion_inputs.h"

namespace thorvald_navigation {

/// One sensor input: odomN (nav_msgs/Odometry), imuN (sensor_msgs/Imu), poseN (PoseWithCovarianceStamped) or
/// twistN (TwistWithCovarianceStamped).
struct EkfInput {
  enum Kind { kOdom, kImu, kPose, kTwist };
  Kind kind = kOdom;
  std::string name;  ///< "odom0", "imu1", ...
  std::string topic;
  int queue_size = 1;
  InputConfig config;
  double status_timeout_s = 1.0;  ///< silent longer than this: the fusion's status is ERROR
  /// Fuses an absolute x or y (a GNSS fix through navsat_transform, a localiser): its timeout is gps_timeout.
  bool position_source() const;
};

struct EkfSettings {
  double frequency = 30.0;             ///< [Hz] output rate
  double sensor_timeout = 1.0 / 30.0;  ///< [s] robot_localization's key; predictions run every cycle anyway
  bool two_d_mode = false;
  bool publish_tf = true;
  std::string map_frame = "map", odom_frame = "odom", base_link_frame = "base_link", world_frame = "odom";
  std::vector<EkfInput> inputs;
  Cov15 process_noise = FusionEkf::defaultProcessNoise();
  Cov15 initial_covariance = Cov15::Identity() * 1e-9;
  State15 initial_state = State15::Zero();
  double gps_timeout = 2.0;    ///< [s] ours: a position source silent this long stops the rover
  double input_timeout = 1.0;  ///< [s] ours: any other input silent this long stops the rover
  /// robot_localization keys that were set but that this node does not implement (named in one warning).
  std::vector<std::string> unsupported_set;
};

/// Reads every robot_localization ekf key (supported ones, and announced-unsupported ones into
/// `unsupported_set`) and the status keys; unknown keys are left for the reader's finish() to report. Throws
/// thorvald_common::ParamError on a wrong value (a config of the wrong length, a gate <= 0, no input at all).
EkfSettings readEkfSettings(thorvald_common::ParamReader& r);

/// robot_localization's `name` (a *_rejection_threshold) [sigma]: a Mahalanobis gate, > 0; infinity (no gate) when
/// not set. odom_fusion reads its gates with it too.
double readRejectionThreshold(thorvald_common::ParamReader& r, const std::string& name);
/// The yaw-rate gate of IMU `imu` ("imu0"): `imu`_angular_velocity_rejection_threshold or, as robot_localization's
/// template names it, `imu`_twist_rejection_threshold; the lower of the two when both are set.
double readImuRateRejectionThreshold(thorvald_common::ParamReader& r, const std::string& imu);

/// The one start-up warning: which keys were set but are not implemented, and what happens instead.
std::string unsupportedWarning(const EkfSettings& s);

}  // namespace thorvald_navigation
