#pragma once

#include <memory>
#include <string>
#include <vector>

#include "thorvald_base/base_calculator.h"

namespace thorvald_base {

/// The default kinematic model (field name `pltf_clc_std::PltfClcStd`): any number of steered (type 0) and fixed
/// (type 1) drives, plus passive wheels. For a twist it finds each wheel's contact velocity about the centre of
/// rotation, steers each steered wheel to it (flipping 180 deg with reversed speed when that is nearer or stays
/// inside +-str_lim) and runs fixed wheels at their forward component.
///
/// Fixed drives and passive wheels forbid sideways motion at their axle: the achievable twist keeps vx and wz and
/// sets vy = -wz * x_axle, x_axle being the mean x of those wheels (a skid-steered robot pivots about it).
class StandardCalculator : public BaseCalculator {
 public:
  void configure(const std::vector<DriveConfig>& drives, const std::vector<PassiveWheelConfig>& passive,
                 const CalculatorOptions& options) override;
  Twist2D achievable(const Twist2D& cmd) const override;
  std::vector<DriveCommand> computeCommands(const Twist2D& cmd, const std::vector<DriveFeedback>& current,
                                            const std::vector<DriveCommand>& previous) override;
  VelocityEstimate estimateTwist(const std::vector<DriveFeedback>& measured) override;
  std::string name() const override { return "thorvald_base::StandardCalculator"; }

 protected:
  std::vector<DriveConfig> drives_;
  std::vector<PassiveWheelConfig> passive_;
  CalculatorOptions options_;
  bool constrained_ = false;  ///< some wheel forbids sideways motion
  double axle_x_ = 0.0;       ///< x of that axle [m]
  std::unique_ptr<VelocityEstimator> estimator_;
};

/// One steered, driven wheel with passive wheels that carry the rest of the robot (Figure 10 d, g).
/// The standard model with the checks this layout needs: exactly one steered drive and at least one passive wheel.
class OneWheelCalculator : public StandardCalculator {
 public:
  void configure(const std::vector<DriveConfig>& drives, const std::vector<PassiveWheelConfig>& passive,
                 const CalculatorOptions& options) override;
  std::string name() const override { return "thorvald_base::OneWheelCalculator"; }
};

/// Two fixed drives on one axle (field name `pltf_clc_2wdiff::PltfClc2WDiff`), in closed form.
class DiffDriveCalculator : public BaseCalculator {
 public:
  void configure(const std::vector<DriveConfig>& drives, const std::vector<PassiveWheelConfig>& passive,
                 const CalculatorOptions& options) override;
  Twist2D achievable(const Twist2D& cmd) const override;
  std::vector<DriveCommand> computeCommands(const Twist2D& cmd, const std::vector<DriveFeedback>& current,
                                            const std::vector<DriveCommand>& previous) override;
  VelocityEstimate estimateTwist(const std::vector<DriveFeedback>& measured) override;
  std::string name() const override { return "thorvald_base::DiffDriveCalculator"; }

 private:
  std::vector<DriveConfig> drives_;
  double axle_x_ = 0.0;
};

}  // namespace thorvald_base
