#include <gtest/gtest.h>

#include <map>
#include <stdexcept>

#include "../src/teleop_params.h"

using namespace thorvald_teleop;
using XmlRpc::XmlRpcValue;

namespace {

JoyTeleopConfig load(std::map<std::string, XmlRpcValue> params) {
  return loadTeleopConfig([&](const std::string& key, XmlRpcValue& v) {
    const auto it = params.find(key);
    if (it == params.end()) return false;
    v = it->second;
    return true;
  });
}

std::string errorOf(std::map<std::string, XmlRpcValue> params) {
  try {
    load(std::move(params));
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
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
  EXPECT_FALSE(c.mapping[TwistField::kLinearY].scale_turbo);  // turbo map default covers x only
  EXPECT_EQ(c.mapping[TwistField::kAngularYaw].axis, 2);
  EXPECT_DOUBLE_EQ(*c.mapping[TwistField::kAngularYaw].scale_turbo, 0.75);  // defaults to the normal yaw scale
}

TEST(TeleopParams, ErrorsNameTheKey) {
  XmlRpcValue bad_map;
  bad_map["w"] = 1;
  EXPECT_EQ(errorOf({{"axis_linear", bad_map}}), "~axis_linear has key 'w', expected one of x, y, z");
  EXPECT_NE(errorOf({{"axis_angular", XmlRpcValue(0.5)}}).find("~axis_angular"), std::string::npos);
  EXPECT_NE(errorOf({{"enable_button", XmlRpcValue("LB")}}).find("~enable_button must be an integer"),
            std::string::npos);
  EXPECT_NE(errorOf({{"initial_mode", XmlRpcValue("sideways")}}).find("omni, drive, turn"), std::string::npos);
  EXPECT_NE(errorOf({{"gain", XmlRpcValue(3.0)}}).find("gain is 3"), std::string::npos);
}
