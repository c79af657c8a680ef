#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "thorvald_sim/mjcf_compiler.h"
#include "thorvald_sim/scene.h"

namespace thorvald_sim {

/// Where a robot is and how it moves: base_link in the world.
struct BodyState {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< [m]
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d linear_body = Eigen::Vector3d::Zero();   ///< velocity in base_link [m/s]
  Eigen::Vector3d angular_body = Eigen::Vector3d::Zero();  ///< [rad/s] in base_link
  double yaw() const;
};

/// One robot inside the simulation.
struct RobotHandle {
  std::string name;       ///< ROS namespace
  std::string root_link;  ///< base_link body name (prefixed)
  int root_body = -1;
  int qpos_adr = -1, qvel_adr = -1;  ///< of its free joint
};

/// Runs one MuJoCo model holding a world and robots. Joint targets are set per actuated joint (named as in the
/// URDF); the bodies move by contact physics. If the physics ever diverges (NaN), the state is reset to the start
/// and the event counted, so a long run never dies. Not thread-safe.
class Simulation {
 public:
  /// Compiles the composed scene. Throws ModelError.
  Simulation(const std::string& scene_xml, const std::vector<RobotSpawn>& robots);

  /// Advances `steps` physics steps.
  void step(int steps = 1);
  /// Back to the start: every robot at its spawn pose, at rest, targets zero; time 0 unless `keep_time` (nodes
  /// under /clock dislike time running backwards).
  void reset(bool keep_time = false);
  double time() const { return data_->time; }
  double timestep() const { return model_->opt.timestep; }

  /// Actuator of a joint by its full URDF name (e.g. "robot1/wheel0"), -1 if none.
  int actuatorOfJoint(const std::string& joint_name) const;
  /// Sets a target: position [rad] for steering joints, velocity [rad/s] for wheels. Non-finite values are
  /// refused (returns false). A wheel's velocity servo never exceeds its drive torque limit (composeScene).
  bool setTarget(int actuator, double value);
  /// The target last set for an actuator (0 for none or after a reset).
  double target(int actuator) const;
  /// Position [rad] and velocity [rad/s] of a joint by name; false if unknown.
  bool jointState(const std::string& joint_name, double* position, double* velocity) const;

  size_t robotCount() const { return robots_.size(); }
  const RobotHandle& robot(size_t i) const { return robots_[i]; }
  BodyState robotState(size_t i) const;
  /// Pose of any body in the world; false if unknown.
  bool bodyPose(const std::string& body, Eigen::Vector3d* pos, Eigen::Quaterniond* q) const;

  /// Fills body accelerations (mj_rnePostConstraint) for IMUs; call after step, before simulateImu.
  void updateAccelerations() { mj_rnePostConstraint(model_.get(), data_.get()); }

  /// Times the physics diverged and was reset.
  unsigned long divergences() const { return divergences_; }
  const mjModel* model() const { return model_.get(); }
  const mjData* data() const { return data_.get(); }
  /// For the actors' mocap poses, set between steps (see actors.h).
  mjData* mutableData() { return data_.get(); }

 private:
  ModelPtr model_;
  DataPtr data_;
  std::vector<RobotHandle> robots_;
  unsigned long divergences_ = 0;
  /// Wheel servos with a torque limit: the actuator, its gain kv [N m s/rad], limit [N m], dof and target.
  struct LimitedWheel {
    int actuator, dof;
    double kv, torque_max, target;
  };
  std::vector<LimitedWheel> limited_;
  std::vector<int> limited_of_actuator_;  ///< actuator -> index in limited_, -1
};

}  // namespace thorvald_sim
