#include "thorvald_base/ros/robot_config_params.h"

#include <ros/param.h>
#include <ros/ros.h>

#include <iomanip>
#include <set>
#include <sstream>

namespace thorvald_base {
namespace {

const char* const kGroups[] = {"base_calculator", "motor_drives", "batteries",      "pipes", "corners",
                               "beams",           "casters",      "passive_wheels", "io",    "implement_can_ids"};

YAML::Node convert(XmlRpc::XmlRpcValue& value, const std::string& source, size_t max_values, size_t& count) {
  if (++count > max_values) {
    throw ConfigError(source, "<size>",
                      "expands to more than " + std::to_string(max_values) +
                          " values (YAML aliases used as a bomb?); a robot file has a few hundred");
  }
  if ((count & 1023) == 0 && !ros::ok() && ros::isInitialized()) {
    throw ConfigError(source, "<size>", "reading interrupted: the node is shutting down");
  }
  switch (value.getType()) {
    case XmlRpc::XmlRpcValue::TypeStruct: {
      YAML::Node map(YAML::NodeType::Map);
      for (auto& kv : value) map[kv.first] = convert(kv.second, source, max_values, count);
      return map;
    }
    case XmlRpc::XmlRpcValue::TypeArray: {
      YAML::Node seq(YAML::NodeType::Sequence);
      for (int i = 0; i < value.size(); ++i) seq.push_back(convert(value[i], source, max_values, count));
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

/// Names directly below `ns` on the parameter server, and whether a ROS 2 `ros__parameters` tree is among them.
struct NamespaceContents {
  std::set<std::string> children;
  std::string ros2_subtree;  ///< e.g. "base_driver/ros__parameters"
};

NamespaceContents contents(const std::string& ns) {
  NamespaceContents out;
  std::vector<std::string> names;
  if (!ros::param::getParamNames(names)) return out;
  const std::string prefix = ns == "/" ? "/" : ns + "/";
  for (const auto& n : names) {
    if (n.size() <= prefix.size() || n.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string rest = n.substr(prefix.size());
    out.children.insert(rest.substr(0, rest.find('/')));
    const auto pos = rest.find("ros__parameters");
    if (out.ros2_subtree.empty() && pos != std::string::npos) out.ros2_subtree = rest.substr(0, pos + 15);
  }
  return out;
}

}  // namespace

YAML::Node toYaml(XmlRpc::XmlRpcValue& value, const std::string& source, size_t max_values) {
  size_t count = 0;
  return convert(value, source, max_values, count);
}

RobotConfig robotConfigFromParams(const ros::NodeHandle& nh, const std::string& file) {
  const std::string ns = nh.getNamespace();
  const std::string source =
      file.empty() ? "robot file in namespace '" + ns + "'" : file + " (loaded into namespace '" + ns + "')";
  const NamespaceContents found = contents(ns);
  YAML::Node root(YAML::NodeType::Map);
  size_t count = 0;
  for (const char* group : kGroups) {
    if (!found.children.count(group) && !nh.hasParam(group)) continue;
    XmlRpc::XmlRpcValue value;
    if (nh.getParam(group, value)) root[group] = convert(value, source, kMaxRobotFileValues, count);
  }
  RobotConfig config;
  if (!root["motor_drives"].IsDefined()) {
    if (!found.ros2_subtree.empty()) {
      throw ConfigError(source, "<top level>",
                        "is a ROS 2 parameters file (node: ros__parameters: ...); the robot file is its sub-tree '" +
                            found.ros2_subtree + "': write that sub-tree to a file of its own and load that");
    }
    XmlRpc::XmlRpcValue whole;
    if (nh.getParam(ns, whole) && whole.getType() == XmlRpc::XmlRpcValue::TypeArray) {
      throw ConfigError(source, "<top level>",
                        "is a list, expected a map of module groups (base_calculator, motor_drives, ...)");
    }
    const bool empty_group = nh.hasParam("motor_drives");
    throw ConfigError(source, "motor_drives",
                      empty_group ? "is empty: a robot needs at least drive0 { node, x, y, r_wheel, ... }"
                                  : "not found on the parameter server (the file is empty, or was not loaded): load "
                                    "the robot file into this namespace first (rosparam load <robot.yaml> " +
                                        ns + ")");
  }
  config = parseRobotConfig(root, source);
  // Keys next to the groups belong to nodes too (robot_description, tf_prefix, node names), so only names that
  // look like a misspelt group are reported, the way the file parser reports unknown top-level keys.
  for (const auto& child : found.children) {
    const std::string near = nearestRobotFileGroup(child);
    if (!near.empty() && near != child) {
      config.warnings.push_back(source + ": " + child + ": unknown top-level key, ignored (did you mean '" + near +
                                "'?)");
    }
  }
  return config;
}

}  // namespace thorvald_base
