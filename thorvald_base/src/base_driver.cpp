#include "thorvald_base/base_driver.h"

#include <sstream>

namespace thorvald_base {

const char* toString(StopReason reason) {
  switch (reason) {
    case StopReason::kNone:
      return "driving";
    case StopReason::kNoCommand:
      return "no command yet";
    case StopReason::kCommandTimeout:
      return "command timed out";
    case StopReason::kSafetyStop:
      return "safety stop";
    case StopReason::kDriveStop:
      return "drive lost or faulted";
  }
  return "unknown";
}

BaseDriver::BaseDriver(RobotConfig config, std::unique_ptr<BaseCalculator> calculator,
                       std::vector<std::unique_ptr<MotorDrive>> drives, std::vector<std::unique_ptr<Battery>> batteries,
                       const BaseDriverOptions& options)
    : config_(std::move(config)),
      calculator_(std::move(calculator)),
      drives_(std::move(drives)),
      batteries_(std::move(batteries)),
      options_(options) {
  if (!calculator_) throw ConfigError(config_.source, "base_calculator", "no kinematic model given");
  if (drives_.size() != config_.drives.size()) {
    throw ConfigError(config_.source, "motor_drives",
                      std::to_string(config_.drives.size()) + " drives in the robot file but " +
                          std::to_string(drives_.size()) + " drive devices");
  }
  if (!(options_.cmd_vel_timeout_s > 0.0)) {
    throw ConfigError("base_driver", "~cmd_vel_timeout", "must be greater than 0 s");
  }
  calculator_->configure(config_.drives, config_.passive_wheels, options_.calculator);
  commands_.resize(drives_.size());
  readDrives();
}

bool BaseDriver::setCommand(const Twist2D& cmd, double now_s) {
  if (!cmd.finite()) {
    ++rejected_commands_;
    return false;
  }
  command_ = cmd;
  command_time_ = now_s;
  return true;
}

void BaseDriver::readDrives() {
  feedback_.resize(drives_.size());
  status_.resize(drives_.size());
  for (size_t i = 0; i < drives_.size(); ++i) {
    feedback_[i] = drives_[i]->feedback();
    status_[i] = drives_[i]->status();
  }
}

void BaseDriver::update(double now_s) {
  readDrives();
  for (size_t i = 0; i < status_.size(); ++i) {
    if (!drive_stop_ && (!status_[i].online || status_[i].fault)) {
      drive_stop_ = true;
      drive_stop_text_ = "drive" + std::to_string(i) + ": " + (status_[i].online ? status_[i].text : "lost");
    }
  }
  Twist2D target;
  if (drive_stop_) {
    stop_reason_ = StopReason::kDriveStop;
  } else if (safety_stop_) {
    stop_reason_ = StopReason::kSafetyStop;
  } else if (command_time_ < 0.0) {
    stop_reason_ = StopReason::kNoCommand;
  } else if (now_s - command_time_ > options_.cmd_vel_timeout_s) {
    stop_reason_ = StopReason::kCommandTimeout;
  } else {
    stop_reason_ = StopReason::kNone;
    target = command_;
  }
  commands_ = calculator_->computeCommands(target, feedback_, commands_);
  for (size_t i = 0; i < drives_.size(); ++i) {
    drives_[i]->setCommand(commands_[i]);
    drives_[i]->update(now_s);
  }
  for (auto& battery : batteries_) battery->update(now_s);
  readDrives();

  const VelocityEstimate previous = velocity_;
  velocity_ = calculator_->estimateTwist(feedback_);
  if (!velocity_.valid) velocity_ = VelocityEstimate{};
  if (last_update_ >= 0.0 && now_s > last_update_) {
    // Trapezoid over the cycle: the mean of the last and the new estimate.
    const Twist2D mean{0.5 * (previous.twist.vx + velocity_.twist.vx), 0.5 * (previous.twist.vy + velocity_.twist.vy),
                       0.5 * (previous.twist.wz + velocity_.twist.wz)};
    odometry_.integrate(mean, velocity_.covariance, now_s - last_update_);
  }
  last_update_ = now_s;
  ++cycles_;
}

bool BaseDriver::clearDriveStop(std::string* message) {
  readDrives();
  for (size_t i = 0; i < status_.size(); ++i) {
    if (!status_[i].online || status_[i].fault) {
      drives_[i]->clearFault();
      if (message) *message = "drive" + std::to_string(i) + " still " + (status_[i].online ? status_[i].text : "lost");
      return false;
    }
  }
  drive_stop_ = false;
  drive_stop_text_.clear();
  if (message) *message = "drive stop cleared";
  return true;
}

bool BaseDriver::setDriveParams(const std::vector<DriveParamChange>& changes, std::string* message) {
  std::vector<DriveConfig> drives = config_.drives;
  for (const auto& change : changes) {
    if (change.drive < -1 || change.drive >= static_cast<int>(drives.size())) {
      if (message)
        *message = "drive " + std::to_string(change.drive) + " does not exist (0.." +
                   std::to_string(drives.size() - 1) + ", or -1 for all)";
      return false;
    }
    for (size_t i = 0; i < drives.size(); ++i) {
      if (change.drive != -1 && change.drive != static_cast<int>(i)) continue;
      if (!setDriveKey(drives[i], change.key, change.value)) {
        if (message) *message = "key '" + change.key + "' cannot be changed at run time (or its value is not finite)";
        return false;
      }
    }
  }
  try {
    for (const auto& d : drives) validateDrive(d, "set_drive_params", "drive" + std::to_string(d.index));
    calculator_->configure(drives, config_.passive_wheels, options_.calculator);
  } catch (const ConfigError& e) {
    calculator_->configure(config_.drives, config_.passive_wheels, options_.calculator);
    if (message) *message = e.what();
    return false;
  }
  config_.drives = drives;
  for (size_t i = 0; i < drives_.size(); ++i) drives_[i]->reconfigure(config_.drives[i]);
  if (message) *message = "applied " + std::to_string(changes.size()) + " change(s)";
  return true;
}

bool BaseDriver::homeSteering(std::string* message) {
  int started = 0;
  for (auto& d : drives_) started += d->startHoming() ? 1 : 0;
  if (message) *message = "homing started on " + std::to_string(started) + " drive(s)";
  return started > 0;
}

std::vector<BatteryReading> BaseDriver::batteries() const {
  std::vector<BatteryReading> out;
  for (const auto& b : batteries_) out.push_back(b->reading());
  return out;
}

}  // namespace thorvald_base
