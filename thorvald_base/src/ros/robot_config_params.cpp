#include "thorvald_base/ros/robot_config_params.h"

#include <ros/param.h>
#include <ros/ros.h>

#include <iomanip>
#include <set>
#include <sstream>

#include "thorvald_common/edit_distance.h"
#include "thorvald_common/ros/bounded_param_read.h"

namespace thorvald_base {

using thorvald_common::getParamBounded;
using thorvald_common::getParamNamesBounded;
using thorvald_common::ParamReadBounds;
using thorvald_common::ParamReadInterrupted;
using thorvald_common::ParamTooLarge;

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

/// Bytes one group of a robot file may take on the parameter server, XML-RPC encoded: a group of 256 modules of ten
/// keys takes about 250 kB.
constexpr size_t kMaxGroupBytes = 1 << 20;
/// Nesting of a group: module, then key (2); lists inside a module add levels, so some room is left.
constexpr size_t kMaxGroupDepth = 8;
/// Bytes of the server's list of parameter names read to find misspelt groups; past it they are not looked for.
constexpr size_t kMaxNameListBytes = 8 << 20;

/// Names directly below `ns` on the parameter server (unknown when the server's list of names is too long), and
/// whether a ROS 2 `ros__parameters` tree is among them.
struct NamespaceContents {
  bool known = false;
  bool ns_is_value = false;  ///< `ns` itself holds a value (a list, a scalar), not a map
  std::set<std::string> children;
  std::string ros2_subtree;  ///< e.g. "base_driver/ros__parameters"
};

NamespaceContents contents(const std::string& ns) {
  NamespaceContents out;
  const auto names = getParamNamesBounded(kMaxNameListBytes);
  if (!names) return out;
  out.known = true;
  const std::string prefix = ns == "/" ? "/" : ns + "/";
  for (const auto& n : *names) {
    if (n == ns) out.ns_is_value = true;
    if (n.size() <= prefix.size() || n.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string rest = n.substr(prefix.size());
    out.children.insert(rest.substr(0, rest.find('/')));
    const auto pos = rest.find("ros__parameters");
    if (out.ros2_subtree.empty() && pos != std::string::npos) out.ros2_subtree = rest.substr(0, pos + 15);
  }
  return out;
}

/// Reads one group (or top-level key) of the robot file, bounded before it is expanded. Returns a value of type
/// TypeInvalid when the key is not set.
XmlRpc::XmlRpcValue readGroup(const ros::NodeHandle& nh, const std::string& group, const std::string& source) {
  ParamReadBounds bounds;
  bounds.max_bytes = kMaxGroupBytes;
  bounds.max_values = kMaxRobotFileValues;  // each group; convert() holds all of them together to it too
  bounds.max_depth = kMaxGroupDepth;
  XmlRpc::XmlRpcValue value;
  try {
    if (!getParamBounded(nh.resolveName(group), value, bounds)) return XmlRpc::XmlRpcValue();
  } catch (const ParamTooLarge& e) {
    throw ConfigError(source, group,
                      std::string(e.what()) +
                          " on the parameter server (YAML aliases used as a bomb?); a robot file's group holds a "
                          "few hundred values in a few kilobytes");
  } catch (const ParamReadInterrupted&) {
    throw ConfigError(source, group, "reading interrupted: the node is shutting down");
  }
  return value;
}

/// The error for a robot file without motor_drives: what the namespace holds instead.
ConfigError missingDrives(const ros::NodeHandle& nh, const std::string& ns, const std::string& source,
                          const NamespaceContents& found) {
  if (!found.ros2_subtree.empty()) {
    return ConfigError(source, "<top level>",
                       "is a ROS 2 parameters file (node: ros__parameters: ...); the robot file is its sub-tree '" +
                           found.ros2_subtree + "': write that sub-tree to a file of its own and load that");
  }
  if (found.ns_is_value) {
    return ConfigError(source, "<top level>",
                       "is a single value (e.g. a list), expected a map of module groups (base_calculator, "
                       "motor_drives, ...)");
  }
  if (nh.hasParam("motor_drives")) {
    return ConfigError(source, "motor_drives", "is empty: a robot needs at least drive0 { node, x, y, r_wheel, ... }");
  }
  const std::string load = "load the robot file into this namespace first (rosparam load <robot.yaml> " + ns + ")";
  if (!found.known) return ConfigError(source, "motor_drives", "not found in " + ns + ": " + load);
  if (found.children.empty()) {
    return ConfigError(source, "motor_drives",
                       "not found on the parameter server: " + ns +
                           " holds no parameters (the file is empty, or was not loaded): " + load);
  }
  size_t distance = 0;
  const std::string nearest =
      thorvald_common::nearestName("motor_drives", {found.children.begin(), found.children.end()}, &distance);
  if (distance <= 3) {
    return ConfigError(source, "motor_drives",
                       "not found in " + ns + "; did you mean " + nearest +
                           "? (the robot file's drives are the group "
                           "motor_drives: drive0, drive1, ...)");
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
  NamespaceContents found;
  try {
    found = contents(ns);
  } catch (const ParamReadInterrupted&) {
    throw ConfigError(source, "<size>", "reading interrupted: the node is shutting down");
  }
  // Only the robot file's own keys are read, each bounded before it is expanded: never the whole namespace, which
  // may hold anything (other nodes' parameters, or what a half-loaded alias bomb left there).
  YAML::Node root(YAML::NodeType::Map);
  size_t count = 0;
  for (const char* group : kGroups) {
    if (found.known ? !found.children.count(group) && !nh.hasParam(group) : !nh.hasParam(group)) continue;
    XmlRpc::XmlRpcValue value = readGroup(nh, group, source);
    if (value.valid()) root[group] = convert(value, source, kMaxRobotFileValues, count);
  }
  if (!root["motor_drives"].IsDefined()) throw missingDrives(nh, ns, source, found);
  RobotConfig config = parseRobotConfig(root, source);
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
