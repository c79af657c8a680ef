#include "thorvald_base/ros/robot_config_params.h"

#include <ros/param.h>
#include <ros/ros.h>

#include <iomanip>
#include <set>
#include <sstream>

#include "thorvald_base/edit_distance.h"

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

/// The error for a namespace without motor_drives: the key there nearest to it, or that the namespace is empty.
ConfigError missingDrives(const std::string& ns, const std::string& source, const NamespaceContents& found) {
  const std::string load = "load the robot file into this namespace first (rosparam load <robot.yaml> " + ns + ")";
  if (found.children.empty()) {
    return ConfigError(source, "motor_drives",
                       "not found on the parameter server: " + ns +
                           " holds no parameters (the file is empty, or was not loaded): " + load);
  }
  size_t distance = 0;
  const std::string nearest = nearestName("motor_drives", {found.children.begin(), found.children.end()}, &distance);
  if (distance <= 3) {
    return ConfigError(source, "motor_drives",
                       "not found in " + ns + "; did you mean " + nearest +
                           "? (the robot file's drives are the group motor_drives: drive0, drive1, ...)");
  }
  return ConfigError(source, "motor_drives",
                     "not found in " + ns + " (the key nearest to it there is " + nearest + "): " + load);
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
    if (nh.hasParam("motor_drives")) {
      throw ConfigError(source, "motor_drives", "is empty: a robot needs at least drive0 { node, x, y, r_wheel, ... }");
    }
    throw missingDrives(ns, source, found);
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
