#include "thorvald_teleop/drive_mode.h"

namespace thorvald_teleop {

const char* driveModeName(DriveMode mode) {
  switch (mode) {
    case DriveMode::kDrive:
      return "drive";
    case DriveMode::kTurnInPlace:
      return "turn";
    case DriveMode::kOmni:
    default:
      return "omni";
  }
}

std::optional<DriveMode> parseDriveMode(const std::string& name) {
  for (DriveMode m : {DriveMode::kOmni, DriveMode::kDrive, DriveMode::kTurnInPlace}) {
    if (name == driveModeName(m)) return m;
  }
  return std::nullopt;
}

VelocityCommand applyDriveMode(const VelocityCommand& command, DriveMode mode) {
  VelocityCommand out;
  switch (mode) {
    case DriveMode::kOmni:
      return command;
    case DriveMode::kDrive:
      out.linear_x = command.linear_x;
      out.angular_z = command.angular_z;
      return out;
    case DriveMode::kTurnInPlace:
      out.angular_z = command.angular_z;
      return out;
  }
  return out;
}

}  // namespace thorvald_teleop
