#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>

#include "cotton_harvester/control/articulation_controller.h"
#include "cotton_harvester/control/deadband_position_controller.h"
#include "cotton_harvester/control/navigation_protocol.h"
#include "cotton_harvester/control/position_pid.h"
#include "cotton_harvester/control/swashplate_mapping.h"

namespace cotton_harvester {
namespace control {

/// Which law drives the swashplate.
enum class PositionControl {
  kDeadbandAware,  ///< DeadbandPositionController: profile, inverse deadband map, feedforward (default)
  kPaperPid,       ///< the paper's PID (Kp 0.7, Ki 0.04, Kd 5.0 on pulses) with eq. 8, kept for comparison
};

std::optional<PositionControl> parsePositionControl(const std::string& name);
std::string toString(PositionControl control);

/// Parameters of the rover controller (paper §2.11–2.12).
struct RoverControllerParams {
  PositionControl position_control = PositionControl::kDeadbandAware;
  DeadbandControllerParams deadband;          ///< kDeadbandAware
  PidGains pid;                               ///< kPaperPid, on encoder pulses
  SwashplateMapping swashplate;               ///< eq. 8
  ArticulationParams articulation;            ///< P control through relays
  double metres_per_pulse = 0.0018;           ///< encoder (§2.11)
  double position_tolerance_m = 0.02;         ///< |error| below which a position target counts as reached
  double velocity_lead_limit_m = 0.3;         ///< velocity mode: how far the moving target may run ahead
  double max_speed_mps = 0.25;                ///< velocity mode: |cmd_vel| limit
  double feedforward_effort_per_mps = 440.0;  ///< velocity mode: effort per m/s of cmd_vel (the
                                              ///< simulated pump gives 0.227 m/s at u = 100; measure it)
  double axle_to_joint_m = 0.91;              ///< for turning a yaw rate into an articulation angle

  /// Empty when sound, otherwise "key: expected ...".
  std::string check() const;
};

/// What the controller asks of the navigation controller this step.
struct RoverOutput {
  double effort = 0.0;  ///< PID output u in [-100, 100]
  double pwm = 90.0;    ///< eq. 8 servo value
  RelayCommand relays;
  DriveCommand command() const;  ///< as a serial frame's content (pwm rounded)
};

/// The rover's movement controller: the deadband-aware position controller (or the paper's PID with the
/// eq. 8 deadband mapping) on the encoder, and the articulation P controller. Two ways in: an absolute position target
/// along the row (from the harvest state machine) or a velocity (cmd_vel from the mux), which moves the position target
/// at that speed so the same PID tracks it. The last one set wins.
class RoverController {
 public:
  explicit RoverController(const RoverControllerParams& params = RoverControllerParams());

  /// Absolute target along the row [m] (encoder distance since start).
  void setPositionTarget(double position_m);
  /// Velocity mode: forward speed [m/s] and yaw rate [rad/s]; the yaw rate sets the articulation.
  void setVelocity(double speed_mps, double yaw_rate_rps);
  /// Ends velocity mode and holds the current position (cmd_vel timed out).
  void holdPosition();
  void setArticulationTarget(double angle_deg);

  /// One control step with a telemetry frame; dt [s] since the previous one.
  RoverOutput update(const Telemetry& telemetry, double dt_s);

  double positionM() const { return position_m_; }
  double targetM() const { return target_m_; }
  double articulationDeg() const { return articulation_deg_; }
  double articulationTargetDeg() const { return articulation_target_deg_; }
  bool targetReached() const;
  bool velocityMode() const { return velocity_mode_; }
  const RoverControllerParams& params() const { return params_; }

 private:
  RoverControllerParams params_;
  PositionPid pid_;
  DeadbandPositionController deadband_;
  ArticulationController articulation_;
  double position_m_ = 0.0;
  double target_m_ = 0.0;
  bool has_telemetry_ = false;
  bool velocity_mode_ = false;
  double speed_mps_ = 0.0;
  double articulation_deg_ = 0.0;
  double articulation_target_deg_ = 0.0;
};

/// Dead-reckoned pose of the articulated rover from the encoder and the articulation angle:
/// the front half's yaw rate is v tan(γ/2) / axle_to_joint for equal half lengths, plus γ' / (1 + cos γ) while the
/// articulation moves (both axles roll without sliding sideways, so the halves swing about the joint).
class ArticulatedOdometry {
 public:
  explicit ArticulatedOdometry(double axle_to_joint_m = 0.91) : axle_to_joint_m_(axle_to_joint_m) {}
  /// Travel along the row since the last update [m], articulation [deg], dt [s].
  void update(double travel_m, double articulation_deg, double dt_s);
  double x() const { return x_; }
  double y() const { return y_; }
  double yaw() const { return yaw_; }
  double speed() const { return speed_; }
  double yawRate() const { return yaw_rate_; }

 private:
  double axle_to_joint_m_;
  double last_articulation_deg_ = std::numeric_limits<double>::quiet_NaN();
  double x_ = 0.0, y_ = 0.0, yaw_ = 0.0, speed_ = 0.0, yaw_rate_ = 0.0;
};

}  // namespace control
}  // namespace cotton_harvester
