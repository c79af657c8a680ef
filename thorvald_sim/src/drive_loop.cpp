#include "thorvald_sim/drive_loop.h"

#include <thorvald_base/standard_calculator.h>

#include <cmath>

namespace thorvald_sim {

std::unique_ptr<thorvald_base::BaseCalculator> makeCalculator(const std::string& name) {
  if (name == "pltf_clc_2wdiff::PltfClc2WDiff" || name == "thorvald_base/DiffDriveCalculator")
    return std::make_unique<thorvald_base::DiffDriveCalculator>();
  if (name == "thorvald_base/OneWheelCalculator") return std::make_unique<thorvald_base::OneWheelCalculator>();
  return std::make_unique<thorvald_base::StandardCalculator>();
}

std::vector<double> suspensionOfDrives(const thorvald_base::RobotConfig& robot) {
  std::vector<double> travel(robot.drives.size(), 0.0);
  bool any = false;
  for (size_t i = 0; i < robot.drives.size(); ++i) {
    double best = 0.6;
    for (const auto& c : robot.corners) {
      const double d = std::hypot(c.x - robot.drives[i].x, c.y - robot.drives[i].y);
      if (d <= best) best = d, travel[i] = std::fabs(c.susp_ang);
    }
    any = any || travel[i] > 0.0;
  }
  return any ? travel : std::vector<double>{};
}

DrivenRobot::DrivenRobot(Simulation& sim, const thorvald_base::RobotConfig& robot, const std::string& tf_prefix,
                         const thorvald_base::BaseDriverOptions& options, EncoderSource encoders)
    : sim_(sim), encoders_(encoders) {
  const std::string p = tf_prefix.empty() ? "" : tf_prefix + "/";
  std::vector<std::unique_ptr<thorvald_base::MotorDrive>> drives;
  for (const auto& d : robot.drives) {
    if (encoders == EncoderSource::kPhysics) {
      auto drive = std::make_unique<PhysicsDrive>(d);
      physics_drives_.push_back(drive.get());
      drives.push_back(std::move(drive));
    } else {
      thorvald_base::SimulatedDriveOptions o;
      o.seed = 1000u + static_cast<unsigned>(d.index);
      drives.push_back(std::make_unique<thorvald_base::SimulatedDrive>(d, o));
    }
    steering_joint_.push_back(p + "steering" + std::to_string(d.index));
    wheel_joint_.push_back(p + "wheel" + std::to_string(d.index));
    const int s = d.steered() ? sim.actuatorOfJoint(p + "steering" + std::to_string(d.index)) : -1;
    const int w = sim.actuatorOfJoint(p + "wheel" + std::to_string(d.index));
    if ((d.steered() && s < 0) || w < 0)
      throw ModelError("robot " + robot.source + ": drive " + std::to_string(d.index) + " has no actuated joint " + p +
                       (w < 0 ? "wheel" : "steering") + std::to_string(d.index) + " in the scene");
    steering_act_.push_back(s);
    wheel_act_.push_back(w);
  }
  driver_ =
      std::make_unique<thorvald_base::BaseDriver>(robot, makeCalculator(robot.base_calculator), std::move(drives),
                                                  std::vector<std::unique_ptr<thorvald_base::Battery>>{}, options);
}

void DrivenRobot::control(double now_s) {
  if (encoders_ == EncoderSource::kPhysics) {
    for (size_t i = 0; i < physics_drives_.size(); ++i) {
      JointMeasurement m;
      sim_.jointState(wheel_joint_[i], &m.wheel_position_rad, &m.wheel_speed_radps);
      if (steering_act_[i] >= 0) sim_.jointState(steering_joint_[i], &m.steering_rad, &m.steering_speed_radps);
      physics_drives_[i]->measure(m, now_s);
    }
    driver_->update(now_s);
    for (size_t i = 0; i < physics_drives_.size(); ++i) {
      const auto& cmd = physics_drives_[i]->command();
      if (steering_act_[i] >= 0) sim_.setTarget(steering_act_[i], cmd.steering_rad);
      sim_.setTarget(wheel_act_[i], cmd.wheel_speed_radps);
    }
    return;
  }
  driver_->update(now_s);
  const auto& fb = driver_->feedback();
  for (size_t i = 0; i < fb.size(); ++i) {
    if (steering_act_[i] >= 0) sim_.setTarget(steering_act_[i], fb[i].steering_rad);
    sim_.setTarget(wheel_act_[i], fb[i].wheel_speed_radps);
  }
}

}  // namespace thorvald_sim
