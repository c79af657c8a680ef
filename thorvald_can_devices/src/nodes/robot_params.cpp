#include "robot_params.h"

#include <xmlrpcpp/XmlRpcValue.h>
#include <yaml-cpp/yaml.h>

#include <iomanip>
#include <sstream>

namespace thorvald_can_devices {
namespace {

YAML::Node toYaml(XmlRpc::XmlRpcValue& v) {
  switch (v.getType()) {
    case XmlRpc::XmlRpcValue::TypeBoolean:
      return YAML::Node(static_cast<bool>(v));
    case XmlRpc::XmlRpcValue::TypeInt:
      return YAML::Node(static_cast<int>(v));
    case XmlRpc::XmlRpcValue::TypeDouble: {
      std::ostringstream s;
      s << std::setprecision(17) << static_cast<double>(v);
      return YAML::Node(s.str());
    }
    case XmlRpc::XmlRpcValue::TypeString:
      return YAML::Node(static_cast<std::string>(v));
    case XmlRpc::XmlRpcValue::TypeArray: {
      YAML::Node n(YAML::NodeType::Sequence);
      for (int i = 0; i < v.size(); ++i) n.push_back(toYaml(v[i]));
      return n;
    }
    case XmlRpc::XmlRpcValue::TypeStruct: {
      YAML::Node n(YAML::NodeType::Map);
      for (auto& kv : v) n[kv.first] = toYaml(kv.second);
      return n;
    }
    default:
      return YAML::Node();
  }
}

}  // namespace

thorvald_base::RobotConfig robotConfigFromParams(const ros::NodeHandle& nh) {
  YAML::Node root(YAML::NodeType::Map);
  for (const char* group : {"base_calculator", "motor_drives", "batteries", "pipes", "corners", "beams", "casters",
                            "passive_wheels", "io"}) {
    XmlRpc::XmlRpcValue value;
    if (nh.getParam(group, value)) root[group] = toYaml(value);
  }
  const std::string source = "robot file in namespace '" + nh.getNamespace() + "'";
  if (!root["motor_drives"].IsDefined()) {
    throw thorvald_base::ConfigError(source, "motor_drives",
                                     "not found on the parameter server: load the robot file into this namespace "
                                     "first (rosparam load <robot.yaml> " +
                                         nh.getNamespace() + ")");
  }
  return thorvald_base::parseRobotConfig(root, source);
}

}  // namespace thorvald_can_devices
