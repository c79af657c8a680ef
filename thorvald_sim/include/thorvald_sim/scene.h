#pragma once

#include <string>
#include <vector>

#include "thorvald_sim/terrain.h"
#include "thorvald_sim/world.h"

namespace thorvald_sim {

/// One robot taking part: its MJCF (from urdfToMjcf) and where it starts.
struct RobotSpawn {
  std::string name;                     ///< ROS namespace of the robot, e.g. "robot1" ("" for the global one)
  std::string mjcf;                     ///< MJCF written by urdfToMjcf
  std::string root_link;                ///< its root body, e.g. "robot1/base_link"
  double x = 0, y = 0, z = 0, yaw = 0;  ///< start pose of base_link in the world [m], [rad]; z above the floor
  /// Suspension module travel per drive index [rad] (the robot file's corner `susp_ang`, suspensionOfDrives):
  /// a drive with travel > 0 gets a passive sprung hinge `suspension<i>` with range +-travel. Empty: rigid.
  std::vector<double> suspension_rad;
};

/// Contact and actuator tuning shared by every robot. Defaults drive a 100-300 kg Thorvald without jitter.
struct SceneOptions {
  double timestep_s = 0.002;
  double wheel_friction = 1.0;      ///< sliding friction coefficient of wheels on the ground
  bool sphere_wheels = true;        ///< wheel contact as a sphere of the wheel radius (one clean contact);
                                    ///< false keeps the URDF's cylinder
  double wheel_kv = 300.0;          ///< velocity servo gain of driven wheels [N m s/rad]
  double wheel_torque_max = 400.0;  ///< limit of the servo's drive term kv * target [N m]
  /// Drive torque limit of every driven wheel: the robot's weight shared by its driven wheels, on the design
  /// slope at the design acceleration. A wheel against an obstacle stalls where sin(slope) + accel / g is below
  /// the wheel's friction coefficient (0.49 < 1.0 by default), as current-limited drives on grippy ground do.
  bool wheel_torque_limit = true;
  double wheel_design_slope_deg = 20.0;
  double wheel_design_accel_mps2 = 1.5;
  double wheel_armature = 0.2;          ///< [kg m^2]
  double steering_kp = 3000.0;          ///< position actuator gain of steering joints [N m/rad]
  double steering_damping = 150.0;      ///< [N m s/rad]
  double steering_armature = 0.5;       ///< [kg m^2]
  double steering_torque_max = 1500.0;  ///< [N m]
  double passive_damping = 0.05;        ///< casters and passive wheels [N m s/rad]
  int camera_max_width = 1280;          ///< largest camera image CameraRenderer can render [px]
  int camera_max_height = 720;
  int render_slices = 32;  ///< tessellation of curved geoms for the cameras (MuJoCo's numslices)
  /// The surface under the wheels (friction and softness of every wheel contact, terrain.h). Dry concrete
  /// writes the scene as before surfaces existed.
  Ground ground = Ground::kDryConcrete;
  /// Suspension hinges (RobotSpawn::suspension_rad): the pivot sits `suspension_arm_m` ahead of the module's
  /// steering axis across the robot (axis along base_link y), so the wheel travels vertically about arm * angle.
  /// The spring lets the static load sag `suspension_sag` of the travel; damping at `suspension_damping_ratio`
  /// of critical for the module's share of the robot's mass on the arm.
  double suspension_arm_m = 0.3;
  double suspension_sag = 0.4;
  double suspension_damping_ratio = 0.5;
};

/// What a joint of a Thorvald URDF is, from its name without the robot's prefix.
enum class JointRole { kSteering, kWheel, kPassive, kOther };
JointRole jointRole(const std::string& name_without_prefix);

/// Joins a world and robots into one MJCF: world geoms, each robot's bodies at its spawn pose with tuned joints
/// and wheel contacts, a position actuator per `steering<i>` and a velocity actuator per `wheel<i>` (named after
/// the joint; the velocity servo is a motor plus joint damping so that the Euler integrator treats its gain
/// implicitly). Robots collide with the world, the actors and each other, not with themselves. Throws ModelError on
/// malformed robot MJCF.
std::string composeScene(const WorldDescription& world, const std::vector<RobotSpawn>& robots,
                         const SceneOptions& options);

}  // namespace thorvald_sim
