#pragma once

#include <optional>
#include <string>

#include "thorvald_teleop/velocity_command.h"

namespace thorvald_teleop {

/// How the pad's command is shaped for a Thorvald base (paper §2.2: one teleop for every module configuration).
enum class DriveMode {
  kOmni,         ///< everything the mapping produces passes: forward, lateral (crab) and yaw together
  kDrive,        ///< forward driving with steering: forward speed and yaw rate only
  kTurnInPlace,  ///< yaw rate only
};

/// "omni", "drive" or "turn".
const char* driveModeName(DriveMode mode);
/// Parses a name of driveModeName(); nullopt for anything else.
std::optional<DriveMode> parseDriveMode(const std::string& name);

/// Zeroes the components `mode` does not drive.
VelocityCommand applyDriveMode(const VelocityCommand& command, DriveMode mode);

}  // namespace thorvald_teleop
