#pragma once

#include <cstdint>

#include "thorvald_base/robot_config.h"

namespace thorvald_can_devices {

/// Conversions between joint units and the Thorvald drive's integers (docs/can_protocols.md).
/// All take the drive's robot-file entry; angles [rad], speeds [rad/s], motor speeds [rpm].
struct ThorvaldScaling {
  /// Wheel speed -> propulsion command, ±1000 full scale (clamped, rounded).
  static int32_t propulsionCommand(double wheel_radps, const thorvald_base::DriveConfig& d);
  /// Propulsion command -> motor speed the drive aims for [rpm].
  static double motorRpmFromCommand(int32_t command, const thorvald_base::DriveConfig& d);
  static double wheelSpeedFromRpm(double motor_rpm, const thorvald_base::DriveConfig& d);
  static double rpmFromWheelSpeed(double wheel_radps, const thorvald_base::DriveConfig& d);
  /// Steering angle -> position command, ±1000 = ±str_lim (clamped, rounded).
  static int32_t steeringCommand(double angle_rad, const thorvald_base::DriveConfig& d);
  static double angleFromSteeringCommand(int32_t command, const thorvald_base::DriveConfig& d);
  /// Steering encoder counts (quadrature, 4 per pulse) <-> steering angle.
  static double steeringFromCount(int32_t count, const thorvald_base::DriveConfig& d);
  static int32_t countFromSteering(double angle_rad, const thorvald_base::DriveConfig& d);
  /// Steering speed <-> steering motor rpm.
  static double steeringSpeedFromRpm(double motor_rpm, const thorvald_base::DriveConfig& d);
  static double steeringRpmFromSpeed(double radps, const thorvald_base::DriveConfig& d);
};

/// Conversions for CiA 402 axes, whose units are encoder increments (4 per pulse) of the motor.
struct Cia402Scaling {
  /// Propulsion axis: wheel speed [rad/s] <-> motor velocity [increments/s].
  static int32_t velocityFromWheelSpeed(double wheel_radps, const thorvald_base::DriveConfig& d);
  static double wheelSpeedFromVelocity(double increments_per_s, const thorvald_base::DriveConfig& d);
  /// Steering axis: angle [rad] <-> position [increments].
  static int32_t positionFromSteering(double angle_rad, const thorvald_base::DriveConfig& d);
  static double steeringFromPosition(double increments, const thorvald_base::DriveConfig& d);
  /// Steering axis speed [increments/s] <-> [rad/s].
  static double steeringSpeedFromVelocity(double increments_per_s, const thorvald_base::DriveConfig& d);
  static double steeringIncrementsPerRad(const thorvald_base::DriveConfig& d);
  static double propulsionIncrementsPerRad(const thorvald_base::DriveConfig& d);
};

}  // namespace thorvald_can_devices
