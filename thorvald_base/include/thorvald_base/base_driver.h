#pragma once

#include <memory>
#include <string>
#include <vector>

#include "thorvald_base/base_calculator.h"
#include "thorvald_base/battery.h"
#include "thorvald_base/motor_drive.h"
#include "thorvald_base/odometry_integrator.h"
#include "thorvald_base/robot_config.h"

namespace thorvald_base {

/// Settings of base_driver's control loop.
struct BaseDriverOptions {
  double cmd_vel_timeout_s = 0.5;  ///< a command older than this stops propulsion [s]
  CalculatorOptions calculator;
};

/// A run-time change of one drive key; drive -1 means every drive.
struct DriveParamChange {
  int drive = -1;
  std::string key;
  double value = 0.0;
};

/// Why propulsion is stopped in this cycle, if it is.
enum class StopReason { kNone, kNoCommand, kCommandTimeout, kSafetyStop, kDriveStop };
const char* toString(StopReason reason);

/// Drives a robot base (paper §3.1): takes twist commands, turns them into drive commands through the kinematic
/// model, runs the drives (simulated or real, behind MotorDrive), estimates velocity from their feedback and
/// integrates odometry. Stops propulsion when commands time out, when the safety stop is latched, and at once
/// when a drive is lost or faulted (latched until cleared). One thread calls every method.
class BaseDriver {
 public:
  /// Throws ConfigError when the model cannot drive the robot or the drive list does not match the robot file.
  BaseDriver(RobotConfig config, std::unique_ptr<BaseCalculator> calculator,
             std::vector<std::unique_ptr<MotorDrive>> drives, std::vector<std::unique_ptr<Battery>> batteries,
             const BaseDriverOptions& options);

  /// Takes a new command at time now_s [s]. Rejects (returns false, counts) a non-finite one.
  bool setCommand(const Twist2D& cmd, double now_s);
  /// One control cycle at time now_s [s]: command the drives, run them, read them, integrate odometry.
  void update(double now_s);

  void setSafetyStop(bool engaged) { safety_stop_ = engaged; }
  /// Leaves the drive stop once every drive is online and fault-free; false with the reason otherwise.
  bool clearDriveStop(std::string* message);
  /// Applies changes of drive keys together after validating all of them; false (nothing changed) otherwise.
  bool setDriveParams(const std::vector<DriveParamChange>& changes, std::string* message);
  bool homeSteering(std::string* message);
  void resetOdometry() { odometry_.reset(); }

  const RobotConfig& config() const { return config_; }
  const BaseCalculator& calculator() const { return *calculator_; }
  const OdometryIntegrator& odometry() const { return odometry_; }
  const VelocityEstimate& velocity() const { return velocity_; }
  const std::vector<DriveCommand>& commands() const { return commands_; }
  const std::vector<DriveFeedback>& feedback() const { return feedback_; }
  const std::vector<DriveStatus>& driveStatus() const { return status_; }
  std::vector<BatteryReading> batteries() const;
  const std::vector<std::unique_ptr<Battery>>& batteryDevices() const { return batteries_; }
  StopReason stopReason() const { return stop_reason_; }
  bool safetyStop() const { return safety_stop_; }
  bool driveStop() const { return drive_stop_; }
  const std::string& driveStopText() const { return drive_stop_text_; }
  unsigned long rejectedCommands() const { return rejected_commands_; }
  unsigned long cycles() const { return cycles_; }
  const Twist2D& lastCommand() const { return command_; }

 private:
  void readDrives();

  RobotConfig config_;
  std::unique_ptr<BaseCalculator> calculator_;
  std::vector<std::unique_ptr<MotorDrive>> drives_;
  std::vector<std::unique_ptr<Battery>> batteries_;
  BaseDriverOptions options_;

  Twist2D command_;
  double command_time_ = -1.0;
  double last_update_ = -1.0;
  bool safety_stop_ = false;
  bool drive_stop_ = false;
  std::string drive_stop_text_;
  StopReason stop_reason_ = StopReason::kNoCommand;
  unsigned long rejected_commands_ = 0;
  unsigned long cycles_ = 0;

  std::vector<DriveCommand> commands_;
  std::vector<DriveFeedback> feedback_;
  std::vector<DriveStatus> status_;
  VelocityEstimate velocity_;
  OdometryIntegrator odometry_;
};

}  // namespace thorvald_base
