#pragma once

#include <random>

#include "thorvald_base/motor_drive.h"

namespace thorvald_base {

/// Imperfections of a simulated drive, so odometry can be tested against a known truth. All off by default.
struct SimulatedDriveOptions {
  double radius_error = 0.0;        ///< true radius = r_wheel * (1 + radius_error); readings assume r_wheel
  double speed_noise_radps = 0.0;   ///< std dev of wheel speed reading noise [rad/s]
  double steering_noise_rad = 0.0;  ///< std dev of steering reading noise [rad]
  double slip_ratio = 0.0;          ///< while slipping the wheel reads (1 + slip_ratio) times its rolling speed
  double slip_fraction = 0.0;       ///< fraction of slip periods in which it slips, drawn at random
  double slip_period_s = 1.0;       ///< length of one slip period [s]
  bool quantize = true;             ///< quantise readings like the encoders (rpm and encoder counts)
  unsigned seed = 1;
};

/// The internal joint simulator of one drive: propulsion follows its command under the acceleration limit
/// `prp_sim_a`, steering moves towards its command at `str_sim_v`, and readings are quantised like the real
/// encoders (motor rpm, steering counts) with optional radius error, noise and slip. It also gives the ideal
/// (truth) joint state: the wheel's true rolling speed and angle.
class SimulatedDrive : public MotorDrive {
 public:
  SimulatedDrive(const DriveConfig& config, const SimulatedDriveOptions& options = {});

  void setCommand(const DriveCommand& command) override { command_ = command; }
  void update(double now_s) override;
  DriveFeedback feedback() const override { return reading_; }
  DriveStatus status() const override;
  void reconfigure(const DriveConfig& config) override;
  bool startHoming() override;

  /// Ideal joint state: wheel speed expressed as if the wheel had radius r_wheel, i.e. rolling speed / r_wheel.
  DriveFeedback truth() const;
  /// Injects a fault (true) or removes it, as a real drive reports one. For tests.
  void setFault(bool fault) { fault_ = fault; }
  const DriveConfig& config() const { return config_; }

 private:
  void step(double dt);
  void read();

  DriveConfig config_;
  SimulatedDriveOptions options_;
  DriveCommand command_;
  double wheel_speed_ = 0.0;     ///< [rad/s] true
  double wheel_position_ = 0.0;  ///< [rad] true
  double steering_ = 0.0;        ///< [rad] true
  double steering_speed_ = 0.0;
  double last_time_ = -1.0;
  bool slipping_ = false;
  long slip_period_index_ = -1;
  double slip_position_extra_ = 0.0;  ///< [rad] extra wheel turn accumulated while slipping
  bool fault_ = false;
  double homing_until_ = -1.0;
  DriveFeedback reading_;
  std::mt19937 rng_;
};

}  // namespace thorvald_base
