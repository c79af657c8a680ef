#pragma once

#include <string>
#include <vector>

#include "thorvald_base/drive_state.h"
#include "thorvald_base/robot_config.h"
#include "thorvald_base/twist2d.h"
#include "thorvald_base/velocity_estimator.h"

namespace thorvald_base {

/// Settings shared by every kinematic model (base_driver parameters).
struct CalculatorOptions {
  std::string estimator = "least_squares";  ///< odometry estimator: least_squares | random_pairs
  unsigned seed = 1;                        ///< seed of the random_pairs estimator
  double aligned_rad = 0.087;  ///< full propulsion when every steered wheel is this close to its target [rad]
  double stopped_rad = 0.785;  ///< no propulsion while a wheel is this far or farther from its target [rad]
};

/// Kinematic model of a robot base, loaded as a plugin named in the robot file (`base_calculator`).
/// It turns a body twist into joint commands and measured joint states back into a body twist. It holds the
/// drives' geometry; `configure` may be called again at run time (e.g. a new wheel radius) and takes effect
/// from the next call. Not thread-safe: one control loop calls it.
class BaseCalculator {
 public:
  virtual ~BaseCalculator() = default;

  /// Takes the drives of the robot. Throws ConfigError if this model cannot drive them.
  virtual void configure(const std::vector<DriveConfig>& drives, const std::vector<PassiveWheelConfig>& passive,
                         const CalculatorOptions& options) = 0;

  /// The part of `cmd` this robot can perform (e.g. no lateral speed with fixed wheels).
  virtual Twist2D achievable(const Twist2D& cmd) const = 0;

  /// Joint commands for `cmd`, one per drive in index order. `current` holds the measured joint states and
  /// `previous` the last commands (a zero command keeps the steering where it was). Sizes equal the number of
  /// drives. Never commands a steering angle outside +-str_lim.
  virtual std::vector<DriveCommand> computeCommands(const Twist2D& cmd, const std::vector<DriveFeedback>& current,
                                                    const std::vector<DriveCommand>& previous) = 0;

  /// Body twist from measured joint states (one per drive, index order).
  virtual VelocityEstimate estimateTwist(const std::vector<DriveFeedback>& measured) = 0;

  /// Plugin name, for diagnostics.
  virtual std::string name() const = 0;
};

}  // namespace thorvald_base
