#include "teleop_params.h"

#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

namespace thorvald_teleop {
namespace {

using XmlRpc::XmlRpcValue;

constexpr int kMaxButton = 255;  ///< highest button index accepted (pads have a few dozen at most)

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

std::string keyList(const std::map<std::string, TwistField>& keys) {
  std::string names;
  for (const auto& k : keys) names += (names.empty() ? "" : ", ") + k.first;
  return names;
}

/// Reads `key`, which must be a map over `keys` (map form of teleop_twist_joy); calls `set` per field given.
/// Returns false when the parameter is not set.
template <typename Set>
bool readFieldMap(const ParamLookup& lookup, const std::string& key, const std::map<std::string, TwistField>& keys,
                  bool integer, const std::string& form_reason, Set set) {
  XmlRpcValue v;
  if (!lookup(key, v)) return false;
  const std::string expected = integer ? "an axis index" : "a number";
  if (v.getType() != XmlRpcValue::TypeStruct) {
    throw std::runtime_error("~" + key + " must be a map over " + keyList(keys) + form_reason);
  }
  for (auto& item : v) {
    const auto field = keys.find(item.first);
    if (field == keys.end()) {
      throw std::runtime_error("~" + key + " has key '" + item.first + "', expected one of " + keyList(keys));
    }
    XmlRpcValue& value = item.second;
    if (integer ? value.getType() != XmlRpcValue::TypeInt : !isNumber(value)) {
      throw std::runtime_error("~" + key + "/" + item.first + " must be " + expected);
    }
    set(field->second, value);
  }
  return true;
}

/// One group of teleop_twist_joy's parameters: linear (x, y, z) or angular (yaw, pitch, roll).
struct Group {
  const std::map<std::string, TwistField>& keys;
  TwistField scalar_field;  ///< the component of the single-number form
  const char* axis_key;
  const char* scale_key;
  const char* turbo_key;
};

/// teleop_twist_joy's two forms. Map form (`axis_*` is a map): the group is exactly what the maps give; a component
/// without a scale (in particular without a turbo scale when `scale_*_turbo` is not set) reads 0 in that mode, so
/// holding turbo then sends a zero twist. Single-number form (`axis_*` an index or not set): one component with
/// upstream's defaults, the turbo scale defaulting to 1.0 (linear) or to the normal scale (angular).
void readGroup(const ParamLookup& lookup, const Group& g, TwistJoyMapping& m) {
  XmlRpcValue axis;
  const bool map_form = lookup(g.axis_key, axis) && axis.getType() == XmlRpcValue::TypeStruct;
  if (map_form) {
    for (const auto& k : g.keys) m[k.second] = FieldMapping();
    const std::string reason =
        std::string(" when ~") + g.axis_key + " is a map (teleop_twist_joy would ignore a single number and read 0)";
    readFieldMap(lookup, g.axis_key, g.keys, true, reason,
                 [&](TwistField f, XmlRpcValue& v) { m[f].axis = static_cast<int>(v); });
    readFieldMap(lookup, g.scale_key, g.keys, false, reason,
                 [&](TwistField f, XmlRpcValue& v) { m[f].scale = toDouble(v); });
    readFieldMap(lookup, g.turbo_key, g.keys, false, reason,
                 [&](TwistField f, XmlRpcValue& v) { m[f].scale_turbo = toDouble(v); });
    return;
  }
  const std::string reason = std::string(" (a map only when ~") + g.axis_key + " is a map too)";
  FieldMapping& f = m[g.scalar_field];
  XmlRpcValue v;
  if (lookup(g.axis_key, v)) {
    if (v.getType() != XmlRpcValue::TypeInt) {
      throw std::runtime_error(std::string("~") + g.axis_key + " must be an axis index or a map over " +
                               keyList(g.keys));
    }
    f.axis = static_cast<int>(v);
  }
  auto readScale = [&](const char* key, std::optional<double>& scale) {
    XmlRpcValue s;
    if (!lookup(key, s)) return;
    if (!isNumber(s)) throw std::runtime_error(std::string("~") + key + " must be a number" + reason);
    scale = toDouble(s);
  };
  readScale(g.scale_key, f.scale);
  const bool turbo_given = lookup(g.turbo_key, v);
  readScale(g.turbo_key, f.scale_turbo);
  // teleop_twist_joy: the turbo yaw scale defaults to the normal one.
  if (!turbo_given && g.scalar_field == TwistField::kAngularYaw) f.scale_turbo = f.scale;
}

void readMapping(thorvald_common::ParamReader& params, const ParamLookup& lookup, TwistJoyMapping& m) {
  m.enable_button = params.integer("enable_button", m.enable_button, -1, kMaxButton);
  m.enable_turbo_button = params.integer("enable_turbo_button", m.enable_turbo_button, -1, kMaxButton);
  m.require_enable_button = params.flag("require_enable_button", m.require_enable_button);
  // The axis and scale maps are read here from their raw values; the reader counts them as read.
  for (const char* key :
       {"axis_linear", "scale_linear", "scale_linear_turbo", "axis_angular", "scale_angular", "scale_angular_turbo"}) {
    params.has(key);
  }
  readGroup(lookup, {kLinearKeys, TwistField::kLinearX, "axis_linear", "scale_linear", "scale_linear_turbo"}, m);
  readGroup(lookup, {kAngularKeys, TwistField::kAngularYaw, "axis_angular", "scale_angular", "scale_angular_turbo"}, m);
}

}  // namespace

JoyTeleopConfig loadTeleopConfig(thorvald_common::ParamReader& params, const ParamLookup& lookup) {
  using thorvald_common::ParamRange;
  JoyTeleopConfig c;
  readMapping(params, lookup, c.mapping);
  TeleopButtons& b = c.buttons;
  const std::pair<const char*, int*> buttons[] = {
      {"mode_button_omni", &b.mode_omni},        {"mode_button_drive", &b.mode_drive},
      {"mode_button_turn", &b.mode_turn},        {"gain_up_button", &b.gain_up},
      {"gain_down_button", &b.gain_down},        {"priority_button", &b.priority},
      {"home_steering_button", &b.home_steering}};
  for (const auto& [key, button] : buttons) *button = params.integer(key, *button, -1, kMaxButton);
  c.gain.initial = params.number("gain", c.gain.initial, ParamRange::above(0.0));
  c.gain.min = params.number("gain_min", c.gain.min, ParamRange::above(0.0));
  c.gain.max = params.number("gain_max", c.gain.max, ParamRange::above(0.0));
  c.gain.step = params.number("gain_step", c.gain.step, ParamRange::above(0.0));
  c.joy_timeout_s = params.number("joy_timeout", c.joy_timeout_s, ParamRange::closed(0.0, 60.0), "s, 0 = off");
  c.initial_mode = *parseDriveMode(params.choice("initial_mode", "omni", {"omni", "drive", "turn"}));
  const std::string error = validateTeleopConfig(c);
  if (!error.empty()) throw thorvald_common::ParamError(params.node() + ": " + error);
  return c;
}

}  // namespace thorvald_teleop
