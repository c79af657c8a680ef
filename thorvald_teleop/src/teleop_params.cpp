#include "teleop_params.h"

#include <map>
#include <stdexcept>

namespace thorvald_teleop {
namespace {

using XmlRpc::XmlRpcValue;

const std::map<std::string, TwistField> kLinearKeys = {
    {"x", TwistField::kLinearX}, {"y", TwistField::kLinearY}, {"z", TwistField::kLinearZ}};
const std::map<std::string, TwistField> kAngularKeys = {
    {"yaw", TwistField::kAngularYaw}, {"pitch", TwistField::kAngularPitch}, {"roll", TwistField::kAngularRoll}};

bool isNumber(const XmlRpcValue& v) {
  return v.getType() == XmlRpcValue::TypeInt || v.getType() == XmlRpcValue::TypeDouble;
}
double toDouble(XmlRpcValue& v) {
  return v.getType() == XmlRpcValue::TypeInt ? static_cast<int>(v) : static_cast<double>(v);
}

int readInt(const ParamLookup& lookup, const std::string& key, int fallback) {
  XmlRpcValue v;
  if (!lookup(key, v)) return fallback;
  if (v.getType() != XmlRpcValue::TypeInt)
    throw std::runtime_error("~" + key + " must be an integer index (-1 = none)");
  return static_cast<int>(v);
}

double readDouble(const ParamLookup& lookup, const std::string& key, double fallback) {
  XmlRpcValue v;
  if (!lookup(key, v)) return fallback;
  if (!isNumber(v)) throw std::runtime_error("~" + key + " must be a number");
  return toDouble(v);
}

bool readBool(const ParamLookup& lookup, const std::string& key, bool fallback) {
  XmlRpcValue v;
  if (!lookup(key, v)) return fallback;
  if (v.getType() != XmlRpcValue::TypeBoolean) throw std::runtime_error("~" + key + " must be true or false");
  return static_cast<bool>(v);
}

/// Reads `key` as a scalar (applies to `scalar_field`) or as a map over `keys`; calls `set` per field given.
/// Returns false when the parameter is not set.
template <typename Set>
bool readFieldParam(const ParamLookup& lookup, const std::string& key, const std::map<std::string, TwistField>& keys,
                    TwistField scalar_field, bool integer, Set set) {
  XmlRpcValue v;
  if (!lookup(key, v)) return false;
  const std::string expected = integer ? "an axis index" : "a number";
  auto check = [&](XmlRpcValue& item, const std::string& where) {
    if (integer ? item.getType() != XmlRpcValue::TypeInt : !isNumber(item)) {
      throw std::runtime_error(where + " must be " + expected);
    }
  };
  if (v.getType() == XmlRpcValue::TypeStruct) {
    for (auto& item : v) {
      const auto field = keys.find(item.first);
      if (field == keys.end()) {
        std::string names;
        for (const auto& k : keys) names += (names.empty() ? "" : ", ") + k.first;
        throw std::runtime_error("~" + key + " has key '" + item.first + "', expected one of " + names);
      }
      check(item.second, "~" + key + "/" + item.first);
      set(field->second, item.second);
    }
    return true;
  }
  check(v, "~" + key + " (or a map of " + expected + "s)");
  set(scalar_field, v);
  return true;
}

void readMapping(const ParamLookup& lookup, TwistJoyMapping& m) {
  m.enable_button = readInt(lookup, "enable_button", m.enable_button);
  m.enable_turbo_button = readInt(lookup, "enable_turbo_button", m.enable_turbo_button);
  m.require_enable_button = readBool(lookup, "require_enable_button", m.require_enable_button);

  struct Group {
    const std::map<std::string, TwistField>& keys;
    TwistField scalar_field;
    const char* axis_key;
    const char* scale_key;
    const char* turbo_key;
  };
  const Group groups[] = {
      {kLinearKeys, TwistField::kLinearX, "axis_linear", "scale_linear", "scale_linear_turbo"},
      {kAngularKeys, TwistField::kAngularYaw, "axis_angular", "scale_angular", "scale_angular_turbo"},
  };
  for (const Group& g : groups) {
    // A parameter that is set replaces the defaults of its whole group, as a map in teleop_twist_joy does.
    TwistJoyMapping given;
    if (readFieldParam(lookup, g.axis_key, g.keys, g.scalar_field, true,
                       [&](TwistField f, XmlRpcValue& v) { given[f].axis = static_cast<int>(v); })) {
      for (const auto& k : g.keys) m[k.second].axis = given[k.second].axis;
    }
    if (readFieldParam(lookup, g.scale_key, g.keys, g.scalar_field, false,
                       [&](TwistField f, XmlRpcValue& v) { given[f].scale = toDouble(v); })) {
      for (const auto& k : g.keys) m[k.second].scale = given[k.second].scale;
    }
    if (readFieldParam(lookup, g.turbo_key, g.keys, g.scalar_field, false,
                       [&](TwistField f, XmlRpcValue& v) { given[f].scale_turbo = toDouble(v); })) {
      for (const auto& k : g.keys) m[k.second].scale_turbo = given[k.second].scale_turbo;
    } else if (g.scalar_field == TwistField::kAngularYaw) {
      // teleop_twist_joy: the turbo yaw scale defaults to the normal one.
      m[TwistField::kAngularYaw].scale_turbo = m[TwistField::kAngularYaw].scale;
    }
  }
}

}  // namespace

JoyTeleopConfig loadTeleopConfig(const ParamLookup& lookup) {
  JoyTeleopConfig c;
  readMapping(lookup, c.mapping);
  TeleopButtons& b = c.buttons;
  b.mode_omni = readInt(lookup, "mode_button_omni", b.mode_omni);
  b.mode_drive = readInt(lookup, "mode_button_drive", b.mode_drive);
  b.mode_turn = readInt(lookup, "mode_button_turn", b.mode_turn);
  b.gain_up = readInt(lookup, "gain_up_button", b.gain_up);
  b.gain_down = readInt(lookup, "gain_down_button", b.gain_down);
  b.priority = readInt(lookup, "priority_button", b.priority);
  b.home_steering = readInt(lookup, "home_steering_button", b.home_steering);
  c.gain.initial = readDouble(lookup, "gain", c.gain.initial);
  c.gain.min = readDouble(lookup, "gain_min", c.gain.min);
  c.gain.max = readDouble(lookup, "gain_max", c.gain.max);
  c.gain.step = readDouble(lookup, "gain_step", c.gain.step);
  c.joy_timeout_s = readDouble(lookup, "joy_timeout", c.joy_timeout_s);
  XmlRpcValue mode;
  if (lookup("initial_mode", mode)) {
    const auto parsed =
        mode.getType() == XmlRpcValue::TypeString ? parseDriveMode(static_cast<std::string>(mode)) : std::nullopt;
    if (!parsed) throw std::runtime_error("~initial_mode must be one of omni, drive, turn");
    c.initial_mode = *parsed;
  }
  const std::string error = validateTeleopConfig(c);
  if (!error.empty()) throw std::runtime_error(error);
  return c;
}

}  // namespace thorvald_teleop
