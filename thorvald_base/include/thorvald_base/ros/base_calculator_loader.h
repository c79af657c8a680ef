#pragma once

#include <pluginlib/class_loader.hpp>

#include <memory>
#include <string>

#include "thorvald_base/base_calculator.h"
#include "thorvald_base/robot_config.h"

namespace thorvald_base {

/// The robot file's kinematics plugin (`base_calculator`) through pluginlib, for every program that reads a robot
/// file: base_driver loads it, urdf_generator checks the name, so both refuse an unknown plugin with one message.
/// Plugins it created must be destroyed before it (pluginlib unloads their library with the loader).
class BaseCalculatorLoader {
 public:
  BaseCalculatorLoader();

  /// Throws ConfigError naming the file, `base_calculator`, the name found and the plugins known (nearest first)
  /// when `config.base_calculator` names no plugin.
  void check(const RobotConfig& config) const;
  /// Checks and creates the plugin (not yet configured). Throws ConfigError.
  std::unique_ptr<BaseCalculator> create(const RobotConfig& config);

 private:
  pluginlib::ClassLoader<BaseCalculator> loader_;
};

}  // namespace thorvald_base
