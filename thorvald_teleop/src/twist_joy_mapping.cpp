#include "thorvald_teleop/twist_joy_mapping.h"

#include <cmath>

namespace thorvald_teleop {

const char* fieldKey(TwistField field) {
  static const char* const kKeys[kTwistFieldCount] = {"x", "y", "z", "yaw", "pitch", "roll"};
  return kKeys[static_cast<std::size_t>(field)];
}

TwistJoyMapping TwistJoyMapping::defaults() {
  TwistJoyMapping m;
  m[TwistField::kLinearX] = {1, 0.5, 1.0};
  m[TwistField::kAngularYaw] = {0, 0.5, 0.5};
  return m;
}

std::string validateMapping(const TwistJoyMapping& mapping) {
  for (std::size_t i = 0; i < kTwistFieldCount; ++i) {
    const FieldMapping& f = mapping.fields[i];
    const std::string key = fieldKey(static_cast<TwistField>(i));
    if (f.axis < -1) return "axis for '" + key + "' is " + std::to_string(f.axis) + ", expected an index >= 0";
    if (f.scale && !std::isfinite(*f.scale)) return "scale for '" + key + "' is not finite, expected a number";
    if (f.scale_turbo && !std::isfinite(*f.scale_turbo)) {
      return "turbo scale for '" + key + "' is not finite, expected a number";
    }
  }
  if (mapping.enable_button < -1)
    return "enable_button is " + std::to_string(mapping.enable_button) + ", expected >= -1";
  if (mapping.enable_turbo_button < -1) {
    return "enable_turbo_button is " + std::to_string(mapping.enable_turbo_button) + ", expected >= -1";
  }
  return {};
}

VelocityCommand commandFromJoy(const JoyState& joy, const TwistJoyMapping& mapping, bool turbo) {
  auto read = [&](TwistField field) {
    const FieldMapping& f = mapping[field];
    const std::optional<double>& scale = turbo ? f.scale_turbo : f.scale;
    if (f.axis < 0 || !scale) return 0.0;
    return axisValue(joy, f.axis) * *scale;
  };
  VelocityCommand c;
  c.linear_x = read(TwistField::kLinearX);
  c.linear_y = read(TwistField::kLinearY);
  c.linear_z = read(TwistField::kLinearZ);
  c.angular_z = read(TwistField::kAngularYaw);
  c.angular_y = read(TwistField::kAngularPitch);
  c.angular_x = read(TwistField::kAngularRoll);
  return c;
}

}  // namespace thorvald_teleop
