#include "thorvald_base/ros/robot_config_params.h"

#include <iomanip>
#include <sstream>

namespace thorvald_base {

YAML::Node toYaml(XmlRpc::XmlRpcValue& value) {
  switch (value.getType()) {
    case XmlRpc::XmlRpcValue::TypeStruct: {
      YAML::Node map(YAML::NodeType::Map);
      for (auto& kv : value) map[kv.first] = toYaml(kv.second);
      return map;
    }
    case XmlRpc::XmlRpcValue::TypeArray: {
      YAML::Node seq(YAML::NodeType::Sequence);
      for (int i = 0; i < value.size(); ++i) seq.push_back(toYaml(value[i]));
      return seq;
    }
    case XmlRpc::XmlRpcValue::TypeBoolean:
      return YAML::Node(static_cast<bool>(value) ? "true" : "false");
    case XmlRpc::XmlRpcValue::TypeInt:
      return YAML::Node(std::to_string(static_cast<int>(value)));
    case XmlRpc::XmlRpcValue::TypeDouble: {
      std::ostringstream s;
      s << std::setprecision(17) << static_cast<double>(value);
      return YAML::Node(s.str());
    }
    case XmlRpc::XmlRpcValue::TypeString:
      return YAML::Node(static_cast<std::string>(value));
    default:
      return YAML::Node(YAML::NodeType::Null);
  }
}

RobotConfig robotConfigFromParams(const ros::NodeHandle& nh) {
  YAML::Node root(YAML::NodeType::Map);
  for (const char* group : {"base_calculator", "motor_drives", "batteries", "pipes", "corners", "beams", "casters",
                            "passive_wheels", "io"}) {
    XmlRpc::XmlRpcValue value;
    if (nh.getParam(group, value)) root[group] = toYaml(value);
  }
  const std::string source = "robot file in namespace '" + nh.getNamespace() + "'";
  if (!root["motor_drives"].IsDefined()) {
    throw ConfigError(source, "motor_drives",
                      "not found on the parameter server: load the robot file into this namespace first "
                      "(rosparam load <robot.yaml> " +
                          nh.getNamespace() + ")");
  }
  return parseRobotConfig(root, source);
}

}  // namespace thorvald_base
