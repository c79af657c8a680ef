#pragma once

#include <functional>
#include <string>

#include <thorvald_common/ros/param_reader.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include "thorvald_teleop/joy_teleop.h"

namespace thorvald_teleop {

/// Looks up one private parameter's raw value; returns false when it is not set.
using ParamLookup = std::function<bool(const std::string& key, XmlRpc::XmlRpcValue& value)>;

/// Reads joy_teleop's parameters: teleop_twist_joy's (enable_button, enable_turbo_button, require_enable_button,
/// axis_linear / axis_angular as an int or a map, scale_linear(_turbo) / scale_angular(_turbo) as a number or a
/// map, with teleop_twist_joy's defaults) and the Thorvald additions. Typed parameters go through the workspace's
/// strict reader `params`; the axis and scale maps are read from `lookup` (the same private parameters, raw).
/// Throws thorvald_common::ParamError or std::runtime_error naming the key and the expected value on anything
/// malformed.
JoyTeleopConfig loadTeleopConfig(thorvald_common::ParamReader& params, const ParamLookup& lookup);

}  // namespace thorvald_teleop
