#include "thorvald_base/base_driver.h"

#include <algorithm>
#include <cmath>
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
    case StopReason::kBatteryStop:
      return "battery policy stop";
  }
  return "unknown";
}

const char* toString(BatteryAction action) {
  switch (action) {
    case BatteryAction::kWarn:
      return "warn";
    case BatteryAction::kSlow:
      return "slow";
    case BatteryAction::kStop:
      return "stop";
  }
  return "unknown";
}

bool parseBatteryAction(const std::string& text, BatteryAction* action) {
  for (BatteryAction a : {BatteryAction::kWarn, BatteryAction::kSlow, BatteryAction::kStop}) {
    if (text == toString(a)) {
      *action = a;
      return true;
    }
  }
  return false;
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
    // Named by file and group: the hardware builds its devices from the same file, so a mismatch means the two
    // read different files (or the hardware skipped a drive).
    const size_t n = config_.drives.size();
    throw ConfigError(config_.source.empty() ? std::string("robot file (unnamed)") : config_.source, "motor_drives",
                      "the group declares " + std::to_string(n) + " drives" +
                          (n ? " (drive0 ... drive" + std::to_string(n - 1) + ")" : std::string()) + " but " +
                          std::to_string(drives_.size()) + " drive devices were given (one per drive is needed)");
  }
  if (!(options_.cmd_vel_timeout_s > 0.0)) {
    throw ConfigError("base_driver", "~cmd_vel_timeout", "must be greater than 0 s");
  }
  validateTwistLimits(options_.limits, "base_driver");
  if (!(options_.min_write_interval_s >= 0.0 && options_.min_write_interval_s <= 1.0)) {
    throw ConfigError("base_driver", "min_write_interval", "must be in [0, 1] s");
  }
  const auto& b = options_.battery;
  const std::pair<const char*, double> battery_values[] = {{"~battery_under_voltage", b.under_voltage_v},
                                                           {"~battery_over_temperature", b.over_temperature_c},
                                                           {"~battery_lost_timeout", b.lost_timeout_s},
                                                           {"~battery_slow_linear_speed", b.slow_linear_mps},
                                                           {"~battery_slow_angular_speed", b.slow_angular_radps}};
  for (const auto& v : battery_values) {
    if (!std::isfinite(v.second) || v.second < 0.0) {
      throw ConfigError("base_driver", v.first,
                        "must be finite and >= 0 (0: check off), found " + std::to_string(v.second));
    }
  }
  limiter_.setLimits(options_.limits);
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

void BaseDriver::checkBatteries(double now_s) {
  const BatteryPolicy& p = options_.battery;
  battery_text_.clear();
  battery_slow_ = battery_stop_ = false;
  battery_heard_.resize(batteries_.size(), now_s);
  const auto act = [&](BatteryAction action, const std::string& what) {
    battery_text_ += (battery_text_.empty() ? "" : "; ") + what + " (" + toString(action) + ")";
    battery_slow_ = battery_slow_ || action == BatteryAction::kSlow;
    battery_stop_ = battery_stop_ || action == BatteryAction::kStop;
  };
  for (size_t i = 0; i < batteries_.size(); ++i) {
    const BatteryReading r = batteries_[i]->reading();
    if (r.online) battery_heard_[i] = now_s;
    const double silent_s = r.age_s >= 0.0 ? r.age_s : now_s - battery_heard_[i];
    if (!r.online) {
      if (p.lost_timeout_s > 0.0 && silent_s > p.lost_timeout_s) {
        act(p.lost, batteries_[i]->name() + " not heard from for " + std::to_string(static_cast<int>(silent_s)) + " s");
      }
      continue;  // its last values are stale: no threshold checks on them
    }
    if (!r.present) continue;
    if (p.under_voltage_v > 0.0 && std::isfinite(r.voltage_v) && r.voltage_v < p.under_voltage_v) {
      act(p.under_voltage, batteries_[i]->name() + " under voltage (" + std::to_string(r.voltage_v) + " V)");
    }
    double hottest = -INFINITY;
    for (double t : r.temperatures_c)
      if (std::isfinite(t)) hottest = std::max(hottest, t);
    if (p.over_temperature_c > 0.0 && hottest > p.over_temperature_c) {
      act(p.over_temperature,
          batteries_[i]->name() + " over temperature (" + std::to_string(static_cast<int>(hottest)) + " degC)");
    }
  }
}

void BaseDriver::applyCommand(double now_s) {
  Twist2D target;
  if (drive_stop_) {
    stop_reason_ = StopReason::kDriveStop;
  } else if (safety_stop_) {
    stop_reason_ = StopReason::kSafetyStop;
  } else if (battery_stop_) {
    stop_reason_ = StopReason::kBatteryStop;
  } else if (command_time_ < 0.0) {
    stop_reason_ = StopReason::kNoCommand;
  } else if (now_s - command_time_ > options_.cmd_vel_timeout_s) {
    stop_reason_ = StopReason::kCommandTimeout;
  } else {
    stop_reason_ = StopReason::kNone;
    target = calculator_->achievable(command_);
  }
  const double dt = last_write_ >= 0.0 ? now_s - last_write_ : 0.0;
  Twist2D executed;
  if (stop_reason_ == StopReason::kNone) {
    if (battery_slow_) {
      SpeedLimiter slow({options_.battery.slow_linear_mps, options_.battery.slow_angular_radps, 0.0, 0.0});
      target = slow.limit(target, 0.0);
    }
    executed = limiter_.limit(target, dt);
  }
  // A stop is never slowed by the acceleration limit: zero is sent at once.
  commands_ = calculator_->computeCommands(executed, feedback_, commands_);
  wheel_factor_ = desaturate(config_.drives, &commands_);
  limiter_.executed({wheel_factor_ * executed.vx, wheel_factor_ * executed.vy, wheel_factor_ * executed.wz});
  last_write_ = now_s;
  for (size_t i = 0; i < drives_.size(); ++i) {
    drives_[i]->setCommand(commands_[i]);
    drives_[i]->update(now_s);
  }
}

bool BaseDriver::writeThrough(double now_s) {
  // Only write-throughs count against the interval: a command right after a cycle's write still goes out at once.
  if (last_write_through_ >= 0.0 && now_s - last_write_through_ < options_.min_write_interval_s) return false;
  applyCommand(now_s);
  last_write_through_ = now_s;
  return true;
}

void BaseDriver::update(double now_s) {
  readDrives();
  if (clear_requested_) {
    if (clear_deadline_ < 0.0) clear_deadline_ = now_s + kClearWindowS;
    bool all_ok = true;
    for (const auto& s : status_) all_ok = all_ok && s.online && !s.fault;
    if (all_ok) {
      drive_stop_ = false;
      drive_stop_text_.clear();
    }
    if (all_ok || now_s > clear_deadline_) clear_requested_ = false;
  }
  for (size_t i = 0; i < status_.size(); ++i) {
    if (!drive_stop_ && (!status_[i].online || status_[i].fault)) {
      drive_stop_ = true;
      drive_stop_text_ = "drive" + std::to_string(i) + ": " + describe(status_[i]);
    }
  }
  for (auto& battery : batteries_) battery->update(now_s);
  checkBatteries(now_s);
  applyCommand(now_s);
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
  std::string bad;
  for (size_t i = 0; i < status_.size(); ++i) {
    if (!status_[i].online || status_[i].fault) {
      drives_[i]->clearFault();
      bad += (bad.empty() ? "" : "; ") + ("drive" + std::to_string(i) + " still ") + describe(status_[i]);
    }
  }
  if (!bad.empty()) {
    clear_requested_ = true;
    clear_deadline_ = -1.0;
    if (message) {
      *message = bad + ": fault reset sent to each; the drive stop is released as soon as every drive reports ok " +
                 "(within " + std::to_string(static_cast<int>(kClearWindowS)) + " s)";
    }
    return false;
  }
  clear_requested_ = false;
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
