#pragma once

#include <array>
#include <optional>
#include <string>

#include "thorvald_teleop/joy_state.h"
#include "thorvald_teleop/velocity_command.h"

namespace thorvald_teleop {

/// The six components a pad can drive, in the key names teleop_twist_joy uses for its maps.
enum class TwistField { kLinearX, kLinearY, kLinearZ, kAngularYaw, kAngularPitch, kAngularRoll };
constexpr std::size_t kTwistFieldCount = 6;

/// "x", "y", "z" (linear) or "yaw", "pitch", "roll" (angular).
const char* fieldKey(TwistField field);

/// How one component is read: axis index and the scales in normal and turbo mode. A component without an axis or
/// without the scale of the current mode reads 0, as in teleop_twist_joy.
struct FieldMapping {
  int axis = -1;
  std::optional<double> scale;        ///< [m/s or rad/s per unit axis]
  std::optional<double> scale_turbo;  ///< [m/s or rad/s per unit axis]
};

/// teleop_twist_joy's configuration, defaults included (linear x on axis 1 at 0.5/1.0, yaw on axis 0 at 0.5/0.5).
struct TwistJoyMapping {
  std::array<FieldMapping, kTwistFieldCount> fields;
  int enable_button = 0;         ///< deadman button; -1 none
  int enable_turbo_button = -1;  ///< turbo button, works without enable; -1 none
  bool require_enable_button = true;

  FieldMapping& operator[](TwistField f) { return fields[static_cast<std::size_t>(f)]; }
  const FieldMapping& operator[](TwistField f) const { return fields[static_cast<std::size_t>(f)]; }

  /// The mapping teleop_twist_joy uses when given no parameters.
  static TwistJoyMapping defaults();
};

/// Returns an empty string or a message naming the bad setting (negative axis other than unset, NaN scale).
std::string validateMapping(const TwistJoyMapping& mapping);

/// The command for `joy` in normal (`turbo` false) or turbo mode.
VelocityCommand commandFromJoy(const JoyState& joy, const TwistJoyMapping& mapping, bool turbo);

}  // namespace thorvald_teleop
