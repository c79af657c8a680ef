#pragma once

#include <memory>

#include "thorvald_base/base_calculator.h"
#include "thorvald_base/base_driver.h"

namespace thorvald_base {

/// A base whose drives do at once what they are told, for checking what base_driver commands (speed limits,
/// geometry) without drive dynamics. Part of thorvald_base_testing (tests and benchmarks), not of the robot's library.

/// A drive whose feedback is its last command.
class IdealDrive : public MotorDrive {
 public:
  void setCommand(const DriveCommand& c) override { command_ = c; }
  void update(double) override {}
  DriveFeedback feedback() const override;
  DriveStatus status() const override { return {}; }
  void reconfigure(const DriveConfig&) override {}

 private:
  DriveCommand command_;
};

/// The kinematic model a robot file names, built directly (no pluginlib): differential drive, one wheel, or the
/// standard model.
std::unique_ptr<BaseCalculator> calculatorFor(const RobotConfig& config);

/// base_driver's core over ideal drives, one per drive of `config`.
std::unique_ptr<BaseDriver> idealDriver(const RobotConfig& config, const BaseDriverOptions& options = {});

/// Sends `cmd` for four 20 ms cycles from *t (steering settles at once on ideal drives), advancing *t, and returns
/// the body twist the wheels then perform, estimated from their commands by the robot's kinematic model.
Twist2D performedTwist(BaseDriver& driver, const Twist2D& cmd, double* t);

}  // namespace thorvald_base
