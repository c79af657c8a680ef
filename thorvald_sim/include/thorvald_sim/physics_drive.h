#pragma once

#include <thorvald_base/motor_drive.h>

namespace thorvald_sim {

/// A drive's joints as the physics simulation measured them (before any encoder quantisation).
struct JointMeasurement {
  double wheel_position_rad = 0.0;
  double wheel_speed_radps = 0.0;
  double steering_rad = 0.0;
  double steering_speed_radps = 0.0;
};

/// What a drive's encoders report for a measured joint state: wheel speed as integer motor rpm, wheel and
/// steering positions in quadrature counts (4 per pulse), through the robot file's gear ratios and pulses per
/// revolution (`prp_gr_rt`, `prp_enc_ppr`, `str_gr_rt`, `str_enc_ppr`), as the Thorvald drive reports them.
thorvald_base::DriveFeedback encoderReading(const thorvald_base::DriveConfig& config, const JointMeasurement& m);

/// One drive module whose joints are moved by the physics simulation (the `thorvald_sim/SimHardware` plugin and
/// DrivenRobot's physics mode): the command goes to the simulator's actuators, the feedback is what MuJoCo
/// measured on the joints, quantised like the encoders. A wheel that slips or stalls against an obstacle shows in
/// the feedback, as on a real robot. The drive is offline (base_driver stops propulsion) until the first
/// measurement and when none arrived for `timeout_s` of (simulated) time.
class PhysicsDrive : public thorvald_base::MotorDrive {
 public:
  explicit PhysicsDrive(const thorvald_base::DriveConfig& config, double timeout_s = 0.5);

  void setCommand(const thorvald_base::DriveCommand& command) override;
  void update(double now_s) override { now_s_ = now_s; }
  thorvald_base::DriveFeedback feedback() const override { return reading_; }
  thorvald_base::DriveStatus status() const override;
  void reconfigure(const thorvald_base::DriveConfig& config) override { config_ = config; }

  /// A measurement taken at (simulated) time `stamp_s`. Non-finite values are refused (false).
  bool measure(const JointMeasurement& m, double stamp_s);
  /// The command to apply: wheel speed [rad/s], steering angle within the robot file's limit [rad].
  const thorvald_base::DriveCommand& command() const { return command_; }
  const thorvald_base::DriveConfig& config() const { return config_; }

 private:
  thorvald_base::DriveConfig config_;
  double timeout_s_;
  thorvald_base::DriveCommand command_;
  thorvald_base::DriveFeedback reading_;
  double last_measure_s_ = -1.0, now_s_ = 0.0;
};

}  // namespace thorvald_sim
