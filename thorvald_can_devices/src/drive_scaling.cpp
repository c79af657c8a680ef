#include "thorvald_can_devices/drive_scaling.h"

#include <cmath>

#include "thorvald_can_devices/can_frame.h"

namespace thorvald_can_devices {
namespace {
constexpr double kRpmPerRadps = 30.0 / M_PI;
}

int32_t ThorvaldScaling::propulsionCommand(double wheel_radps, const thorvald_base::DriveConfig& d) {
  return clampToI32(rpmFromWheelSpeed(wheel_radps, d) * 1000.0 / d.prp_max_rpm, -1000, 1000);
}
double ThorvaldScaling::motorRpmFromCommand(int32_t command, const thorvald_base::DriveConfig& d) {
  return command * d.prp_max_rpm / 1000.0;
}
double ThorvaldScaling::wheelSpeedFromRpm(double motor_rpm, const thorvald_base::DriveConfig& d) {
  return motor_rpm / d.prp_gr_rt / kRpmPerRadps;
}
double ThorvaldScaling::rpmFromWheelSpeed(double wheel_radps, const thorvald_base::DriveConfig& d) {
  return wheel_radps * d.prp_gr_rt * kRpmPerRadps;
}
int32_t ThorvaldScaling::steeringCommand(double angle_rad, const thorvald_base::DriveConfig& d) {
  return clampToI32(1000.0 * angle_rad / d.str_lim, -1000, 1000);
}
double ThorvaldScaling::angleFromSteeringCommand(int32_t command, const thorvald_base::DriveConfig& d) {
  return command * d.str_lim / 1000.0;
}
double ThorvaldScaling::steeringFromCount(int32_t count, const thorvald_base::DriveConfig& d) {
  return count / (d.str_enc_ppr * 4.0 * d.str_gr_rt) * 2.0 * M_PI;
}
int32_t ThorvaldScaling::countFromSteering(double angle_rad, const thorvald_base::DriveConfig& d) {
  return clampToI32(angle_rad / (2.0 * M_PI) * d.str_enc_ppr * 4.0 * d.str_gr_rt, INT32_MIN, INT32_MAX);
}
double ThorvaldScaling::steeringSpeedFromRpm(double motor_rpm, const thorvald_base::DriveConfig& d) {
  return motor_rpm / d.str_gr_rt / kRpmPerRadps;
}
double ThorvaldScaling::steeringRpmFromSpeed(double radps, const thorvald_base::DriveConfig& d) {
  return radps * d.str_gr_rt * kRpmPerRadps;
}

double Cia402Scaling::propulsionIncrementsPerRad(const thorvald_base::DriveConfig& d) {
  return d.prp_gr_rt * d.prp_enc_ppr * 4.0 / (2.0 * M_PI);
}
double Cia402Scaling::steeringIncrementsPerRad(const thorvald_base::DriveConfig& d) {
  return d.str_gr_rt * d.str_enc_ppr * 4.0 / (2.0 * M_PI);
}
int32_t Cia402Scaling::velocityFromWheelSpeed(double wheel_radps, const thorvald_base::DriveConfig& d) {
  return clampToI32(wheel_radps * propulsionIncrementsPerRad(d), INT32_MIN, INT32_MAX);
}
double Cia402Scaling::wheelSpeedFromVelocity(double v, const thorvald_base::DriveConfig& d) {
  return v / propulsionIncrementsPerRad(d);
}
int32_t Cia402Scaling::positionFromSteering(double angle_rad, const thorvald_base::DriveConfig& d) {
  return clampToI32(angle_rad * steeringIncrementsPerRad(d), INT32_MIN, INT32_MAX);
}
double Cia402Scaling::steeringFromPosition(double p, const thorvald_base::DriveConfig& d) {
  return p / steeringIncrementsPerRad(d);
}
double Cia402Scaling::steeringSpeedFromVelocity(double v, const thorvald_base::DriveConfig& d) {
  return v / steeringIncrementsPerRad(d);
}

}  // namespace thorvald_can_devices
