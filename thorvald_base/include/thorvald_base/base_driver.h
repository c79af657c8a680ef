#pragma once

#include <memory>
#include <string>
#include <vector>

#include "thorvald_base/base_calculator.h"
#include "thorvald_base/battery.h"
#include "thorvald_base/motor_drive.h"
#include "thorvald_base/odometry_integrator.h"
#include "thorvald_base/robot_config.h"
#include "thorvald_base/speed_limiter.h"

namespace thorvald_base {

/// What base_driver does about one kind of battery problem.
enum class BatteryAction { kWarn, kSlow, kStop };
const char* toString(BatteryAction action);
/// Parses warn | slow | stop; false for anything else.
bool parseBatteryAction(const std::string& text, BatteryAction* action);

/// Battery policy: thresholds and what each problem does. A threshold of 0 turns its check off.
struct BatteryPolicy {
  double under_voltage_v = 0.0;  ///< below this pack voltage [V]
  BatteryAction under_voltage = BatteryAction::kSlow;
  double over_temperature_c = 60.0;  ///< any cell temperature above this [degC]
  BatteryAction over_temperature = BatteryAction::kStop;
  double lost_timeout_s = 3.0;  ///< a fitted battery not heard from for this long is lost [s]
  BatteryAction lost = BatteryAction::kStop;
  double slow_linear_mps = 0.3;     ///< speed limit while an action is `slow` [m/s]
  double slow_angular_radps = 0.3;  ///< turn rate limit while an action is `slow` [rad/s]
};

/// Settings of base_driver's control loop.
struct BaseDriverOptions {
  double cmd_vel_timeout_s = 0.5;  ///< a command older than this stops propulsion [s]
  CalculatorOptions calculator;
  TwistLimits limits;  ///< body twist limits (0: none); wheel limits come from the robot file (prp_max_rpm)
  /// A new command is written through to the drives at once, but not more often than this [s].
  double min_write_interval_s = 0.002;
  BatteryPolicy battery;
};

/// A run-time change of one drive key; drive -1 means every drive.
struct DriveParamChange {
  int drive = -1;
  std::string key;
  double value = 0.0;
};

/// Why propulsion is stopped in this cycle, if it is.
enum class StopReason { kNone, kNoCommand, kCommandTimeout, kSafetyStop, kDriveStop, kBatteryStop };
const char* toString(StopReason reason);

/// Drives a robot base (paper §3.1): takes twist commands, turns them into drive commands through the kinematic
/// model, runs the drives (simulated or real, behind MotorDrive), estimates velocity from their feedback and
/// integrates odometry. Limits the body twist (velocity, acceleration) and scales all wheel speeds by one factor
/// when a wheel would exceed its drive's maximum, so the centre of rotation is kept. Stops propulsion when commands
/// time out, when the safety stop is latched, at once when a drive is lost or faulted (latched until cleared), and
/// as the battery policy says. One thread calls every method.
class BaseDriver {
 public:
  /// Throws ConfigError when the model cannot drive the robot or the drive list does not match the robot file.
  BaseDriver(RobotConfig config, std::unique_ptr<BaseCalculator> calculator,
             std::vector<std::unique_ptr<MotorDrive>> drives, std::vector<std::unique_ptr<Battery>> batteries,
             const BaseDriverOptions& options);

  /// Takes a new command at time now_s [s]. Rejects (returns false, counts) a non-finite one.
  bool setCommand(const Twist2D& cmd, double now_s);
  /// Sends the current command to the drives now (after setCommand), with the same limits and stop checks as a
  /// cycle, without reading the drives or integrating odometry. Returns false (nothing sent) when the last
  /// write-through was less than min_write_interval_s ago; the next write-through or cycle then sends it.
  bool writeThrough(double now_s);
  /// One control cycle at time now_s [s]: command the drives, run them, read them, integrate odometry.
  void update(double now_s);

  void setSafetyStop(bool engaged) { safety_stop_ = engaged; }
  /// Leaves the drive stop at once when every drive is online and fault-free (true). Otherwise asks every lost or
  /// faulted drive to clear its fault and returns false naming them all; the stop is then released in the first
  /// cycle, within 2 s, in which every drive reports ok (one call clears any number of faulted drives).
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
  /// The twist last sent to the drives, after the limits and the common wheel factor.
  const Twist2D& executedTwist() const { return limiter_.previous(); }
  /// The common wheel factor of the last write (1: no wheel at its limit).
  double wheelFactor() const { return wheel_factor_; }
  /// Battery problems of the last cycle, in words ("" when none), and the strongest action they ask for.
  const std::string& batteryText() const { return battery_text_; }
  bool batterySlow() const { return battery_slow_; }

 private:
  void readDrives();
  void applyCommand(double now_s);
  void checkBatteries(double now_s);

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
  SpeedLimiter limiter_;
  double last_write_ = -1.0, last_write_through_ = -1.0;
  double wheel_factor_ = 1.0;
  std::string battery_text_;
  bool battery_slow_ = false, battery_stop_ = false;
  std::vector<double> battery_heard_;
  static constexpr double kClearWindowS = 2.0;  ///< a clear request waits this long for the drives to recover [s]
  bool clear_requested_ = false;
  double clear_deadline_ = -1.0;

  std::vector<DriveCommand> commands_;
  std::vector<DriveFeedback> feedback_;
  std::vector<DriveStatus> status_;
  VelocityEstimate velocity_;
  OdometryIntegrator odometry_;
};

}  // namespace thorvald_base
