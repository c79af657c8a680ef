#pragma once

#include <Eigen/Geometry>
#include <stdexcept>
#include <string>
#include <vector>

#include "thorvald_sim/sensors.h"

namespace YAML {
class Node;
}

namespace thorvald_sim {

enum class SensorType { kLidar, kUltrasonic, kDepthCamera, kImu };

/// One sensor a simulated robot carries, as declared in its sensor YAML.
struct SensorConfig {
  SensorType type = SensorType::kLidar;
  std::string name;                               ///< unique per robot; names its frame `<prefix>/<name>`
  std::string parent = "base_link";               ///< link it is mounted on (without prefix)
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero();  ///< mount position in the parent link [m]
  Eigen::Vector3d rpy = Eigen::Vector3d::Zero();  ///< mount roll, pitch, yaw [rad]
  double rate_hz = 10.0;
  std::string topic;  ///< relative topic; defaults per type (scan, ultrasonic/<name>, camera, imu)
  unsigned seed = 1;
  Realism realism = Realism::kIdeal;  ///< the file's `realism`, or the sensor's own; copied into its spec
  LidarSpec lidar;
  UltrasonicSpec ultrasonic;
  DepthCameraSpec depth;
  bool color = false;  ///< depth camera also publishes an RGB image of the same optics
  ImuSpec imu;

  Eigen::Matrix3d mountRotation() const;
};

/// A sensor YAML that cannot be used: names the sensor, the key and what was expected.
class SensorConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Parses `sensors: [ {type: lidar|ultrasonic|depth_camera|imu, name: ..., ...}, ... ]`. Unknown keys are errors
/// (a typo must not silently drop a sensor). Throws SensorConfigError.
///
/// Realism: `realism: ideal|datasheet` next to `sensors` sets every sensor's profile (default ideal); a sensor's own
/// `realism` overrides it. A sensor names its `device` (lidar: utm_30lx; ultrasonic: generic; depth_camera: d400;
/// imu: um7 or phidget_1044; the first is the default) and may override the figures of its datasheet model in a
/// `model:` map (keys in the README). An unknown profile, device or model key, or a value out of range, is refused
/// naming it.
std::vector<SensorConfig> parseSensorConfig(const YAML::Node& root, const std::string& source);
std::vector<SensorConfig> loadSensorConfigFile(const std::string& path);

}  // namespace thorvald_sim
