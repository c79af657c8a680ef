#pragma once

#include <xmlrpcpp/XmlRpcValue.h>
#include <yaml-cpp/yaml.h>

namespace thorvald_base {

/// Converts a parameter-server tree into the YAML tree the robot-file parser reads, so a robot file loaded with
/// `rosparam load` and one read from disk go through the same checks.
YAML::Node toYaml(XmlRpc::XmlRpcValue& value);

}  // namespace thorvald_base
