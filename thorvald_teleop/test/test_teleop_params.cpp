#include <gtest/gtest.h>

#include <initializer_list>
#include <map>
#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

#include "../src/ros/teleop_params.h"

using namespace thorvald_teleop;
using XmlRpc::XmlRpcValue;

namespace {

/// Private parameters from a map, as the parameter server would give them.
class MapSource : public thorvald_common::ParamSource {
 public:
  explicit MapSource(std::map<std::string, XmlRpcValue> params) : params_(std::move(params)) {}
  bool get(const std::string& name, XmlRpcValue& value) const override {
    const auto it = params_.find(name);
    if (it == params_.end()) return false;
    value = it->second;
    return true;
  }
  std::vector<std::string> names() const override {
    std::vector<std::string> out;
    for (const auto& p : params_) out.push_back(p.first);
    return out;
  }

 private:
  std::map<std::string, XmlRpcValue> params_;
};

JoyTeleopConfig load(const std::map<std::string, XmlRpcValue>& params, std::vector<std::string>* unread = nullptr) {
  thorvald_common::ParamReader reader(std::make_unique<MapSource>(params), "/joy_teleop");
  const JoyTeleopConfig c = loadTeleopConfig(reader, [&](const std::string& key, XmlRpcValue& v) {
    const auto it = params.find(key);
    if (it == params.end()) return false;
    v = it->second;
    return true;
  });
  if (unread) *unread = reader.unread();
  return c;
}

std::string errorOf(std::map<std::string, XmlRpcValue> params) {
  try {
    load(std::move(params));
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

XmlRpcValue fieldMap(std::initializer_list<std::pair<const char*, XmlRpcValue>> items) {
  XmlRpcValue v;
  for (const auto& [key, value] : items) v[key] = value;
  return v;
}

}  // namespace

TEST(TeleopParams, DefaultsAreTeleopTwistJoys) {
  const JoyTeleopConfig c = load({});
  EXPECT_EQ(c.mapping.enable_button, 0);
  EXPECT_EQ(c.mapping.enable_turbo_button, -1);
  EXPECT_EQ(c.mapping[TwistField::kLinearX].axis, 1);
  EXPECT_DOUBLE_EQ(*c.mapping[TwistField::kLinearX].scale, 0.5);
  EXPECT_DOUBLE_EQ(*c.mapping[TwistField::kLinearX].scale_turbo, 1.0);
  EXPECT_EQ(c.mapping[TwistField::kAngularYaw].axis, 0);
  EXPECT_DOUBLE_EQ(*c.mapping[TwistField::kAngularYaw].scale_turbo, 0.5);
  EXPECT_EQ(c.buttons.priority, -1);
  EXPECT_DOUBLE_EQ(c.gain.initial, 1.0);
  EXPECT_DOUBLE_EQ(c.joy_timeout_s, 0.0);
}

TEST(TeleopParams, IntegerAndMapForms) {
  XmlRpcValue axis_linear;
  axis_linear["x"] = 4;
  axis_linear["y"] = 3;
  XmlRpcValue scale_linear;
  scale_linear["x"] = 2;  // an int where a double is expected
  scale_linear["y"] = 0.25;
  const JoyTeleopConfig c = load({{"axis_linear", axis_linear},
                                  {"scale_linear", scale_linear},
                                  {"axis_angular", XmlRpcValue(2)},
                                  {"scale_angular", XmlRpcValue(0.75)}});
  EXPECT_EQ(c.mapping[TwistField::kLinearX].axis, 4);
  EXPECT_EQ(c.mapping[TwistField::kLinearY].axis, 3);
  EXPECT_DOUBLE_EQ(*c.mapping[TwistField::kLinearX].scale, 2.0);
  EXPECT_DOUBLE_EQ(*c.mapping[TwistField::kLinearY].scale, 0.25);
  // Map form without scale_linear_turbo: no turbo scale at all (teleop_twist_joy's map form has no defaults).
  EXPECT_FALSE(c.mapping[TwistField::kLinearX].scale_turbo);
  EXPECT_FALSE(c.mapping[TwistField::kLinearY].scale_turbo);
  EXPECT_EQ(c.mapping[TwistField::kLinearZ].axis, -1);
  EXPECT_EQ(c.mapping[TwistField::kAngularYaw].axis, 2);
  EXPECT_DOUBLE_EQ(*c.mapping[TwistField::kAngularYaw].scale_turbo, 0.75);  // defaults to the normal yaw scale
}

// teleop_twist_joy's config/ps3-holonomic.config.yaml: map form, no turbo scales, a turbo button. Upstream sends a
// zero twist while turbo is held (the turbo scale map is empty); so must we.
TEST(TeleopParams, MapFormWithoutTurboScalesGivesAZeroTwistUnderTurbo) {
  const JoyTeleopConfig c = load({{"axis_linear", fieldMap({{"x", 1}, {"y", 0}})},
                                  {"scale_linear", fieldMap({{"x", 0.4}, {"y", 0.4}})},
                                  {"axis_angular", fieldMap({{"yaw", 2}})},
                                  {"scale_angular", fieldMap({{"yaw", 0.5}})},
                                  {"enable_button", XmlRpcValue(10)},
                                  {"enable_turbo_button", XmlRpcValue(8)}});
  for (std::size_t i = 0; i < kTwistFieldCount; ++i) EXPECT_FALSE(c.mapping.fields[i].scale_turbo) << i;
  EXPECT_EQ(c.mapping[TwistField::kAngularYaw].axis, 2);
  EXPECT_FALSE(c.mapping[TwistField::kAngularPitch].scale);  // the map replaces the single-number defaults

  JoyState joy;
  joy.axes = {0.5, -0.25, 0.75};
  joy.buttons.assign(11, 0);
  const VelocityCommand turbo = commandFromJoy(joy, c.mapping, true);
  EXPECT_EQ(turbo.linear_x, 0.0);
  EXPECT_EQ(turbo.linear_y, 0.0);
  EXPECT_EQ(turbo.angular_z, 0.0);
  const VelocityCommand normal = commandFromJoy(joy, c.mapping, false);
  EXPECT_DOUBLE_EQ(normal.linear_x, -0.25 * 0.4);
  EXPECT_DOUBLE_EQ(normal.linear_y, 0.5 * 0.4);
  EXPECT_DOUBLE_EQ(normal.angular_z, 0.75 * 0.5);

  // Through the whole teleop: turbo held without enable sends zero twists (not nothing, not motion).
  JoyTeleop teleop(c);
  joy.buttons[8] = 1;
  const TeleopActions a = teleop.onJoy(joy, 0.0);
  ASSERT_TRUE(a.command);
  EXPECT_EQ(a.command->linear_x, 0.0);
  EXPECT_EQ(a.command->linear_y, 0.0);
  EXPECT_EQ(a.command->angular_z, 0.0);
}

TEST(TeleopParams, MapFormWithoutScalesReadsZero) {
  const JoyTeleopConfig c = load({{"axis_linear", fieldMap({{"x", 1}})}});
  EXPECT_EQ(c.mapping[TwistField::kLinearX].axis, 1);
  EXPECT_FALSE(c.mapping[TwistField::kLinearX].scale);
  // The angular group is untouched: single-number defaults.
  EXPECT_DOUBLE_EQ(*c.mapping[TwistField::kAngularYaw].scale, 0.5);
}

TEST(TeleopParams, MixedFormsAreRefused) {
  EXPECT_EQ(errorOf({{"axis_linear", fieldMap({{"x", 1}})}, {"scale_linear", XmlRpcValue(0.5)}}),
            "~scale_linear must be a map over x, y, z when ~axis_linear is a map (teleop_twist_joy would ignore a "
            "single number and read 0)");
  EXPECT_EQ(errorOf({{"axis_angular", XmlRpcValue(3)}, {"scale_angular_turbo", fieldMap({{"yaw", 1.0}})}}),
            "~scale_angular_turbo must be a number (a map only when ~axis_angular is a map too)");
  EXPECT_EQ(errorOf({{"scale_linear", fieldMap({{"x", 1.0}})}}),
            "~scale_linear must be a number (a map only when ~axis_linear is a map too)");
}

TEST(TeleopParams, ErrorsNameTheKey) {
  XmlRpcValue bad_map;
  bad_map["w"] = 1;
  EXPECT_EQ(errorOf({{"axis_linear", bad_map}}), "~axis_linear has key 'w', expected one of x, y, z");
  EXPECT_EQ(errorOf({{"axis_angular", XmlRpcValue(0.5)}}),
            "~axis_angular must be an axis index or a map over pitch, roll, yaw");
  EXPECT_EQ(errorOf({{"axis_linear", fieldMap({{"x", 0.5}})}}), "~axis_linear/x must be an axis index");
  EXPECT_EQ(errorOf({{"enable_button", XmlRpcValue("LB")}}),
            "/joy_teleop: parameter ~enable_button: found the string 'LB', expected an integer in [-1, 255]");
  EXPECT_EQ(errorOf({{"initial_mode", XmlRpcValue("sideways")}}),
            "/joy_teleop: parameter ~initial_mode: found the string 'sideways', expected one of 'omni', 'drive', "
            "'turn'");
  EXPECT_EQ(errorOf({{"joy_timeout", XmlRpcValue(-0.5)}}),
            "/joy_teleop: parameter ~joy_timeout: found the number -0.5, expected a number in [0, 60] [s, 0 = off]");
  EXPECT_EQ(errorOf({{"require_enable_button", XmlRpcValue("no")}}),
            "/joy_teleop: parameter ~require_enable_button: found the string 'no', expected true or false");
  EXPECT_NE(errorOf({{"gain", XmlRpcValue(3.0)}}).find("/joy_teleop: gain is 3"), std::string::npos);
}

TEST(TeleopParams, UnreadParametersAreReported) {
  std::vector<std::string> unread;
  load({{"scale_linaer", XmlRpcValue(1.0)}, {"axis_linear", fieldMap({{"x", 1}})}, {"gain", XmlRpcValue(0.5)}},
       &unread);
  EXPECT_EQ(unread, std::vector<std::string>{"scale_linaer"});
}
