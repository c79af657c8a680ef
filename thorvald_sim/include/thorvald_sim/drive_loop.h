#pragma once

#include <memory>
#include <string>
#include <vector>

#include <thorvald_base/base_driver.h>
#include <thorvald_base/simulated_drive.h>

#include "thorvald_sim/physics_drive.h"
#include "thorvald_sim/simulation.h"

namespace thorvald_sim {

/// Makes the kinematic model a robot file names (the same choice base_driver makes through pluginlib):
/// differential for `pltf_clc_2wdiff::PltfClc2WDiff` / `thorvald_base/DiffDriveCalculator`, one-wheel for
/// `thorvald_base/OneWheelCalculator`, the standard model otherwise.
std::unique_ptr<thorvald_base::BaseCalculator> makeCalculator(const std::string& base_calculator);

/// Suspension travel per drive index [rad] for RobotSpawn::suspension_rad: the |`susp_ang`| of the robot file's
/// corner nearest the drive (within 0.6 m; the suspension module sits between the frame corner and the steering
/// module); 0 for a drive without one. Empty when no corner has suspension (the robot stays rigid).
std::vector<double> suspensionOfDrives(const thorvald_base::RobotConfig& robot);

/// Where base_driver's joint states come from.
enum class EncoderSource {
  kJointSimulator,  ///< base_driver's own joint simulator (the papers' design); MuJoCo follows it
  kPhysics,         ///< MuJoCo's joints, measured and quantised like the encoders (PhysicsDrive)
};

/// base_driver in process, coupled to one robot of a Simulation the way the node couples them over ROS. With the
/// joint simulator, each control cycle the driver runs its joint simulator and the simulated joints become the
/// MuJoCo actuators' targets (steering position, wheel velocity); in physics mode the driver's commands become the
/// targets and MuJoCo's measured joints its feedback (what the `thorvald_sim/SimHardware` plugin does over
/// topics). For tests, benchmarks and the demo that need no ROS master. The caller steps the Simulation.
class DrivenRobot {
 public:
  /// `tf_prefix` prefixes the joint names as in the URDF. Throws thorvald_base::ConfigError, ModelError when a
  /// joint has no actuator.
  DrivenRobot(Simulation& sim, const thorvald_base::RobotConfig& robot, const std::string& tf_prefix,
              const thorvald_base::BaseDriverOptions& options = {},
              EncoderSource encoders = EncoderSource::kJointSimulator);

  void command(const thorvald_base::Twist2D& cmd, double now_s) { driver_->setCommand(cmd, now_s); }
  /// One control cycle at simulated time `now_s`: driver update, then actuator targets.
  void control(double now_s);

  thorvald_base::BaseDriver& driver() { return *driver_; }
  const thorvald_base::BaseDriver& driver() const { return *driver_; }

 private:
  Simulation& sim_;
  EncoderSource encoders_;
  std::vector<std::string> steering_joint_, wheel_joint_;
  std::vector<PhysicsDrive*> physics_drives_;  ///< owned by the driver; physics mode only
  std::unique_ptr<thorvald_base::BaseDriver> driver_;
  std::vector<int> steering_act_, wheel_act_;  ///< per drive; -1 for no steering
};

}  // namespace thorvald_sim
