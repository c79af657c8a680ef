#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "thorvald_sim/imu_model.h"
#include "thorvald_sim/lidar_model.h"
#include "thorvald_sim/ray_caster.h"
#include "thorvald_sim/realism.h"
#include "thorvald_sim/stereo_models.h"
#include "thorvald_sim/ultrasonic_model.h"

namespace thorvald_sim {

/// Planar scanner in the sensor's x-y plane (x forward, z up), like a Hokuyo UTM-30LX.
struct LidarSpec {
  double angle_min_rad = -2.356, angle_max_rad = 2.356;
  int samples = 541;
  double range_min_m = 0.1, range_max_m = 30.0;
  double noise_m = 0.01;  ///< std dev of range noise [m] (ideal)
  Realism realism = Realism::kIdeal;
  LidarModel model;  ///< the datasheet profile's errors (noise_m unused there)
};

/// Ultrasonic range finder looking along its x axis with a cone of `fov_rad` (sensor_msgs/Range convention).
/// It reports the nearest echo inside the cone.
struct UltrasonicSpec {
  double fov_rad = 0.35;
  double range_min_m = 0.02, range_max_m = 2.0;
  double noise_m = 0.002;
  int rings = 3;  ///< rays: one on the axis plus `rings` rings of `rays_per_ring`
  int rays_per_ring = 8;
  Realism realism = Realism::kIdeal;
  UltrasonicModel model;  ///< datasheet: echoes lost on oblique surfaces
};

/// Depth camera in the optical frame convention (z forward, x right, y down). Active stereo errors: depth noise
/// growing with the square of depth, random dropouts, and no depth on surfaces seen at grazing angles.
struct DepthCameraSpec {
  int width = 640, height = 480;
  double hfov_rad = 1.2;  ///< horizontal field of view; square pixels
  double focal_px = 0.0;  ///< fx = fy [px]; 0: from hfov_rad
  double cx_px = -1.0;    ///< principal point [px]; negative: the image centre ((width - 1) / 2)
  double cy_px = -1.0;
  double range_min_m = 0.3, range_max_m = 8.0;
  double noise_coeff = 0.002;       ///< depth std dev = noise_coeff * z^2 [1/m]
  double dropout = 0.01;            ///< probability that a valid pixel has no depth
  double grazing_limit_rad = 1.35;  ///< no depth where the view hits a surface more obliquely than this
  Realism realism = Realism::kIdeal;
  ActiveStereoModel stereo;  ///< datasheet: replaces noise_coeff and dropout (grazing_limit still applies)
};

/// Colour camera (same optics as the depth camera): each pixel takes the colour of the geom it sees.
struct ColorCameraSpec {
  int width = 640, height = 480;
  double hfov_rad = 1.2;
  double focal_px = 0.0;  ///< as DepthCameraSpec
  double cx_px = -1.0, cy_px = -1.0;
  double range_max_m = 50.0;
  uint8_t background[3] = {170, 200, 235};  ///< what a ray that hits nothing sees
};

/// Pinhole intrinsics of an image of width x height with horizontal field of view hfov: fx = fy, centred.
struct Intrinsics {
  double fx, fy, cx, cy;
};
Intrinsics intrinsics(int width, int height, double hfov_rad);
/// A camera's intrinsics: its focal length and principal point where given, else from its field of view.
template <typename Spec>
Intrinsics intrinsics(const Spec& s) {
  Intrinsics k = intrinsics(s.width, s.height, s.hfov_rad);
  if (s.focal_px > 0.0) k.fx = k.fy = s.focal_px;
  if (s.cx_px >= 0.0) k.cx = s.cx_px;
  if (s.cy_px >= 0.0) k.cy = s.cy_px;
  return k;
}

struct DepthImage {
  int width = 0, height = 0;
  std::vector<Eigen::Vector3f> points;  ///< row-major, optical frame [m]; NaN where there is no depth
};

struct ColorImage {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;  ///< row-major rgb8
};

/// Sensor pose: `origin` and `rotation` (columns: the sensor's axes in the world).
struct SensorPose {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
};

/// Pose a fraction `f` of the way from `a` to `b` (origins linear, rotations by slerp).
SensorPose interpolatePose(const SensorPose& a, const SensorPose& b, double f);
/// Pose after moving for `dt_s` with linear velocity `v_mps` and angular velocity `w_radps` (both in the world).
SensorPose advancePose(const SensorPose& p, const Eigen::Vector3d& v_mps, const Eigen::Vector3d& w_radps, double dt_s);

/// Where a sensor at `pose` on `body` will be after `dt_s` if the body keeps its present velocity (mjData's).
SensorPose sweepEnd(const mjModel* model, const mjData* data, int body, const SensorPose& pose, double dt_s);

/// One scan; +inf where nothing is in range. Noise drawn from `rng`. Datasheet profile: the LidarModel's errors;
/// with `sweep_end` (the pose one mirror turn, model.sweep_s, after `pose`), beam i is cast from the pose at its own
/// time, a fraction (angle_i - angle_min) / 2 pi of the way (the scan distorted by the motion, as on a robot).
std::vector<float> simulateLidar(RayCaster& caster, const SensorPose& pose, const LidarSpec& spec, std::mt19937& rng,
                                 const SensorPose* sweep_end = nullptr);
/// Nearest echo in the cone [m]; +inf if none within range_max. Datasheet profile: rays that meet their surface
/// beyond model.max_incidence_rad give no echo.
double simulateUltrasonic(RayCaster& caster, const SensorPose& pose, const UltrasonicSpec& spec, std::mt19937& rng);
/// `pose` is the optical frame (z forward). The ideal profile only (the node's cameras go through depthFromView).
DepthImage simulateDepth(RayCaster& caster, const SensorPose& pose, const DepthCameraSpec& spec, std::mt19937& rng);
ColorImage simulateColor(RayCaster& caster, const mjModel* model, const SensorPose& pose, const ColorCameraSpec& spec);

}  // namespace thorvald_sim

namespace thorvald_sim {

/// Inertial measurement unit noise.
struct ImuSpec {
  double accel_noise_mps2 = 0.02;   ///< std dev [m/s^2] (ideal)
  double gyro_noise_radps = 0.002;  ///< std dev [rad/s] (ideal)
  Realism realism = Realism::kIdeal;
  ImuModel model;  ///< datasheet: white noise, drifting biases, scale factors (kept in an ImuErrors)
};

/// What an IMU reads, in its own frame: orientation in the world, rates, specific force (gravity reaction included:
/// +9.81 on z when level and still).
struct ImuReading {
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();     ///< [rad/s]
  Eigen::Vector3d linear_acceleration = Eigen::Vector3d::Zero();  ///< [m/s^2]
};

/// IMU on `body` turned by `mount` (sensor axes in the body). Needs mj_rnePostConstraint to have run on `data`
/// (Simulation::updateAccelerations). Read at the body's origin: lever-arm accelerations are not modelled. Datasheet
/// profile: `errors` (the sensor's drifting state, made from spec.model) applies its errors at time `t_s` [s]; the
/// orientation stays the true one.
ImuReading simulateImu(const mjModel* model, const mjData* data, int body, const Eigen::Matrix3d& mount,
                       const ImuSpec& spec, std::mt19937& rng, ImuErrors* errors = nullptr, double t_s = 0.0);

}  // namespace thorvald_sim
