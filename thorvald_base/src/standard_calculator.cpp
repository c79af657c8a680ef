#include "thorvald_base/standard_calculator.h"

#include <algorithm>
#include <cmath>

#include "thorvald_base/angles.h"
#include "thorvald_base/steering_optimizer.h"

namespace thorvald_base {
namespace {
constexpr double kStill_mps = 1e-6;  // a wheel slower than this has no direction to steer to
}  // namespace

void StandardCalculator::configure(const std::vector<DriveConfig>& drives,
                                   const std::vector<PassiveWheelConfig>& passive, const CalculatorOptions& options) {
  if (drives.empty())
    throw ConfigError("base_calculator", "motor_drives", "the standard model needs at least one drive");
  auto estimator = makeVelocityEstimator(options.estimator, options.seed);
  if (!estimator) {
    throw ConfigError("base_driver", "~odometry_estimator",
                      "expected 'least_squares' or 'random_pairs', found '" + options.estimator + "'");
  }
  const bool any_steered = std::any_of(drives.begin(), drives.end(), [](const DriveConfig& d) { return d.steered(); });
  if (options.estimator == "random_pairs" && !any_steered) {
    throw ConfigError("base_driver", "~odometry_estimator",
                      "'random_pairs' cannot see rotation on a robot without steered drives (the normals of fixed "
                      "wheels never intersect); use 'least_squares'");
  }
  validateDriveSpacing(drives, "base_calculator");
  validateObservability(drives, passive, "base_calculator");
  drives_ = drives;
  passive_ = passive;
  options_ = options;
  estimator_ = std::move(estimator);
  double sum_x = 0.0;
  int fixed = 0;
  for (const auto& d : drives_) {
    if (!d.steered()) {
      sum_x += d.x;
      ++fixed;
    }
  }
  for (const auto& p : passive_) {
    sum_x += p.x;
    ++fixed;
  }
  constrained_ = fixed > 0;
  axle_x_ = constrained_ ? sum_x / fixed : 0.0;
}

Twist2D StandardCalculator::achievable(const Twist2D& cmd) const {
  if (!constrained_) return cmd;
  return {cmd.vx, -cmd.wz * axle_x_, cmd.wz};
}

std::vector<DriveCommand> StandardCalculator::computeCommands(const Twist2D& cmd,
                                                              const std::vector<DriveFeedback>& current,
                                                              const std::vector<DriveCommand>& previous) {
  const Twist2D t = achievable(cmd);
  std::vector<DriveCommand> out(drives_.size());
  double worst_error = 0.0;
  for (size_t i = 0; i < drives_.size(); ++i) {
    const DriveConfig& d = drives_[i];
    const double kept = i < previous.size() ? previous[i].steering_rad : 0.0;
    out[i].steering_rad = d.steered() ? std::clamp(kept, -d.str_lim, d.str_lim) : 0.0;
    // Contact-point velocity of a wheel at (x, y) for rotation about the centre implied by the twist.
    const double vx = t.vx - t.wz * d.y;
    const double vy = t.vy + t.wz * d.x;
    if (!d.steered()) {
      out[i].wheel_speed_radps = vx / d.r_wheel;
      continue;
    }
    const double speed = std::hypot(vx, vy);
    if (speed < kStill_mps) continue;  // zero command, or this wheel sits at the centre: keep its angle
    const double measured = i < current.size() && current[i].valid ? current[i].steering_rad : out[i].steering_rad;
    const SteeringChoice choice = chooseSteering(std::atan2(vy, vx), measured, d.str_lim);
    out[i].steering_rad = choice.angle_rad;
    out[i].wheel_speed_radps = choice.speed_sign * choice.speed_factor * speed / d.r_wheel;
    worst_error = std::max(worst_error, std::fabs(choice.angle_rad - measured));
  }
  const double scale = alignmentScale(worst_error, options_.aligned_rad, options_.stopped_rad);
  for (auto& c : out) c.wheel_speed_radps *= scale;
  return out;
}

VelocityEstimate StandardCalculator::estimateTwist(const std::vector<DriveFeedback>& measured) {
  std::vector<WheelObservation> wheels;
  wheels.reserve(drives_.size() + passive_.size());
  for (size_t i = 0; i < drives_.size() && i < measured.size(); ++i) {
    if (!measured[i].valid) continue;
    const DriveConfig& d = drives_[i];
    wheels.push_back(
        {d.x, d.y, d.steered() ? measured[i].steering_rad : 0.0, measured[i].wheel_speed_radps * d.r_wheel, true});
  }
  if (wheels.empty()) return {};
  for (const auto& p : passive_) wheels.push_back({p.x, p.y, 0.0, 0.0, false});
  return estimator_->estimate(wheels);
}

void OneWheelCalculator::configure(const std::vector<DriveConfig>& drives,
                                   const std::vector<PassiveWheelConfig>& passive, const CalculatorOptions& options) {
  if (drives.size() != 1 || !drives[0].steered()) {
    throw ConfigError("base_calculator", "motor_drives",
                      "the one-wheel model needs exactly one steered (type 0) drive, found " +
                          std::to_string(drives.size()) + " drive(s)");
  }
  if (passive.empty()) {
    throw ConfigError("base_calculator", "passive_wheels",
                      "the one-wheel model needs passive_wheels: they fix the axle the robot turns about");
  }
  StandardCalculator::configure(drives, passive, options);
}

void DiffDriveCalculator::configure(const std::vector<DriveConfig>& drives,
                                    const std::vector<PassiveWheelConfig>& /*passive*/,
                                    const CalculatorOptions& options) {
  // Its closed form is the least-squares fit of two wheels on one axle; random pairs of two parallel wheels
  // never intersect and would report no rotation.
  if (options.estimator != "least_squares") {
    throw ConfigError("base_driver", "~odometry_estimator",
                      "the two-wheel differential model estimates odometry in closed form (least squares); "
                      "expected 'least_squares', found '" +
                          options.estimator + "'");
  }
  if (drives.size() != 2) {
    throw ConfigError(
        "base_calculator", "motor_drives",
        "the two-wheel differential model needs exactly 2 drives, found " + std::to_string(drives.size()));
  }
  if (std::fabs(drives[0].y - drives[1].y) < 1e-3) {
    throw ConfigError("base_calculator", "motor_drives", "the two differential wheels must have different y");
  }
  if (std::fabs(drives[0].x - drives[1].x) > 1e-3) {
    throw ConfigError("base_calculator", "motor_drives", "the two differential wheels must share one axle (same x)");
  }
  validateDriveSpacing(drives, "base_calculator");
  drives_ = drives;
  axle_x_ = 0.5 * (drives[0].x + drives[1].x);
}

Twist2D DiffDriveCalculator::achievable(const Twist2D& cmd) const { return {cmd.vx, -cmd.wz * axle_x_, cmd.wz}; }

std::vector<DriveCommand> DiffDriveCalculator::computeCommands(const Twist2D& cmd,
                                                               const std::vector<DriveFeedback>& /*current*/,
                                                               const std::vector<DriveCommand>& /*previous*/) {
  std::vector<DriveCommand> out(2);
  for (size_t i = 0; i < 2; ++i) out[i].wheel_speed_radps = (cmd.vx - cmd.wz * drives_[i].y) / drives_[i].r_wheel;
  return out;
}

VelocityEstimate DiffDriveCalculator::estimateTwist(const std::vector<DriveFeedback>& measured) {
  VelocityEstimate out;
  if (measured.size() < 2 || !measured[0].valid || !measured[1].valid) return out;
  const double s0 = measured[0].wheel_speed_radps * drives_[0].r_wheel;
  const double s1 = measured[1].wheel_speed_radps * drives_[1].r_wheel;
  // s_i = vx - wz * y_i for both wheels.
  const double wz = (s0 - s1) / (drives_[1].y - drives_[0].y);
  out.twist = {s0 + wz * drives_[0].y, -wz * axle_x_, wz};
  out.covariance = Eigen::Matrix3d::Identity() * 1e-4;
  out.valid = out.twist.finite();
  return out;
}

}  // namespace thorvald_base
