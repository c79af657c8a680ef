#include "thorvald_base/testing/ideal_base.h"

#include <vector>

#include "thorvald_base/standard_calculator.h"

namespace thorvald_base {

DriveFeedback IdealDrive::feedback() const {
  DriveFeedback f;
  f.valid = true;
  f.wheel_speed_radps = command_.wheel_speed_radps;
  f.steering_rad = command_.steering_rad;
  return f;
}

std::unique_ptr<BaseCalculator> calculatorFor(const RobotConfig& config) {
  if (config.base_calculator.find("2WDiff") != std::string::npos ||
      config.base_calculator.find("DiffDrive") != std::string::npos)
    return std::make_unique<DiffDriveCalculator>();
  if (config.base_calculator.find("OneWheel") != std::string::npos) return std::make_unique<OneWheelCalculator>();
  return std::make_unique<StandardCalculator>();
}

std::unique_ptr<BaseDriver> idealDriver(const RobotConfig& config, const BaseDriverOptions& options) {
  std::vector<std::unique_ptr<MotorDrive>> drives;
  for (size_t i = 0; i < config.drives.size(); ++i) drives.push_back(std::make_unique<IdealDrive>());
  return std::make_unique<BaseDriver>(config, calculatorFor(config), std::move(drives),
                                      std::vector<std::unique_ptr<Battery>>{}, options);
}

Twist2D performedTwist(BaseDriver& driver, const Twist2D& cmd, double* t) {
  for (int k = 0; k < 4; ++k) {
    *t += 0.02;
    driver.setCommand(cmd, *t);
    driver.update(*t);
  }
  std::vector<DriveFeedback> fb;
  for (const auto& c : driver.commands()) {
    DriveFeedback f;
    f.valid = true;
    f.wheel_speed_radps = c.wheel_speed_radps;
    f.steering_rad = c.steering_rad;
    fb.push_back(f);
  }
  std::unique_ptr<BaseCalculator> calc = calculatorFor(driver.config());
  calc->configure(driver.config().drives, driver.config().passive_wheels, {});
  return calc->estimateTwist(fb).twist;
}

}  // namespace thorvald_base
