// Reading a robot file: the key tables of every module type, the module groups, the top level. The checks that
// run-time changes share are in robot_config_validation.cpp.
#include "thorvald_base/robot_config.h"

#include <yaml-cpp/yaml.h>

#include <map>
#include <string>
#include <vector>

#include "module_fields.h"
#include "thorvald_base/angles.h"
#include "thorvald_common/edit_distance.h"

namespace thorvald_base {
namespace {

using detail::Bounds;
using detail::Field;
using detail::intField;
using detail::numberField;
using detail::readFields;
using detail::ScalarReader;
using detail::textField;

// Physical ranges (docs/robot_file.md lists the same). Positions: any Thorvald module sits within a few metres of
// base_link; kMaxModuleOffset_m leaves room for the largest frames and refuses typing slips such as 1e6.
constexpr double kPos = kMaxModuleOffset_m;
constexpr Bounds kPosition{-kPos, kPos, "m"};
constexpr Bounds kHeight{-2.0, 5.0, "m"};
constexpr Bounds kMesh{0, 9, ""};

}  // namespace

const std::vector<detail::Field<DriveConfig>>& detail::driveFields() {
  using D = DriveConfig;
  static const std::vector<Field<D>> fields = {
      intField<D>({"node"}, true, &D::node, {1, 127, "(CAN node id)"}),
      numberField<D>({"x"}, true, &D::x, kPosition),
      numberField<D>({"y"}, true, &D::y, kPosition),
      intField<D>({"type"}, false, &D::type, {0, 1, "(0 steered, 1 fixed)"}),
      intField<D>({"leg_mesh"}, false, &D::leg_mesh, kMesh),
      numberField<D>({"r_wheel"}, true, &D::r_wheel, {0.02, 1.0, "m"}),
      numberField<D>({"w_wheel"}, false, &D::w_wheel, {0.01, 0.5, "m"}),
      numberField<D>({"prp_gr_rt"}, true, &D::prp_gr_rt, {0.1, 1000.0, "(motor turns per wheel turn)"}),
      numberField<D>({"prp_enc_ppr"}, true, &D::prp_enc_ppr, {1.0, 1e6, "(pulses per motor turn)"}),
      numberField<D>({"prp_max_rpm"}, true, &D::prp_max_rpm, {10.0, 30000.0, "rpm"}),
      numberField<D>({"prp_sim_a"}, false, &D::prp_sim_a, {0.01, 20.0, "m/s^2"}),
      numberField<D>({"str_gr_rt"}, true, &D::str_gr_rt, {0.1, 1000.0, "(motor turns per steering turn)"}),
      numberField<D>({"str_enc_ppr"}, true, &D::str_enc_ppr, {1.0, 1e6, "(pulses per turn)"}),
      numberField<D>({"str_lim", "str_llm"}, true, &D::str_lim, {0.01, 3.1416, "rad"}),
      numberField<D>({"str_sim_v", "str_stm_v"}, false, &D::str_sim_v, {0.01, 50.0, "rad/s"}),
      textField<D>({"protocol"}, false, &D::protocol),
  };
  return fields;
}

namespace {

using detail::driveFields;

/// Steering keys are required only for steered (type-0) drives.
bool driveKeyRequired(const DriveConfig& d, const Field<DriveConfig>& f) {
  if (!f.required) return false;
  return d.steered() || f.names[0].rfind("str_", 0) != 0;
}

const std::vector<Field<BatteryConfig>>& batteryFields() {
  using B = BatteryConfig;
  static const std::vector<Field<B>> fields = {
      intField<B>({"id"}, false, &B::id, {-1, 127, "(-1: no battery)"}),
      intField<B>({"type"}, false, &B::type, {0, 1, "(0 empty enclosure, 1 battery)"}),
      numberField<B>({"x"}, false, &B::x, kPosition),
      numberField<B>({"y"}, false, &B::y, kPosition),
      numberField<B>({"z"}, false, &B::z, kHeight),
      numberField<B>({"yaw"}, false, &B::yaw, {-2 * kPi, 2 * kPi, "rad"}),
      intField<B>({"bat_mesh"}, false, &B::bat_mesh, kMesh),
      {{"with_battery"},
       false,
       [](B& b, const ScalarReader& r, const YAML::Node& n, const std::string& k) {
         b.with_battery = r.boolean(n, k);
       }},
      // Older files: `node`, where -1 means no battery and the bus id was node - 344.
      {{"node"},
       false,
       [](B& b, const ScalarReader& r, const YAML::Node& n, const std::string& k) {
         const int node = r.integer(n, k);
         b.id = node < 0 ? -1 : node - 344;
       }},
  };
  return fields;
}

const std::vector<Field<PipeConfig>>& pipeFields() {
  using P = PipeConfig;
  static const std::vector<Field<P>> fields = {
      numberField<P>({"x1"}, true, &P::x1, kPosition),
      numberField<P>({"y1"}, true, &P::y1, kPosition),
      numberField<P>({"x2"}, true, &P::x2, kPosition),
      numberField<P>({"y2"}, true, &P::y2, kPosition),
      numberField<P>({"height"}, false, &P::height, {0.0, 5.0, "m"}),
      numberField<P>({"space"}, false, &P::space, {0.0, 2.0, "m"}),
  };
  return fields;
}

const std::vector<Field<CornerConfig>>& cornerFields() {
  using C = CornerConfig;
  static const std::vector<Field<C>> fields = {
      intField<C>({"type"}, false, &C::type, kMesh),
      intField<C>({"corner_mesh"}, false, &C::corner_mesh, kMesh),
      numberField<C>({"x"}, true, &C::x, kPosition),
      numberField<C>({"y"}, true, &C::y, kPosition),
      numberField<C>({"z"}, false, &C::z, kHeight),
      numberField<C>({"space"}, false, &C::space, {0.0, 2.0, "m"}),
      numberField<C>({"susp_ang"}, false, &C::susp_ang, {-kPi, kPi, "rad"}),
  };
  return fields;
}

const std::vector<Field<BeamConfig>>& beamFields() {
  using B = BeamConfig;
  static const std::vector<Field<B>> fields = {textField<B>({"start"}, true, &B::start),
                                               textField<B>({"end"}, true, &B::end)};
  return fields;
}

const std::vector<Field<PassiveWheelConfig>>& passiveWheelFields() {
  using W = PassiveWheelConfig;
  static const std::vector<Field<W>> fields = {
      numberField<W>({"x"}, true, &W::x, kPosition),
      numberField<W>({"y"}, true, &W::y, kPosition),
      numberField<W>({"z_top"}, false, &W::z_top, {0.0, 5.0, "m"}),
      numberField<W>({"r_wheel"}, false, &W::r_wheel, {0.01, 1.0, "m"}),
      numberField<W>({"w_wheel"}, false, &W::w_wheel, {0.005, 0.5, "m"}),
      numberField<W>({"offset"}, false, &W::offset, {-1.0, 1.0, "m"}),
  };
  return fields;
}

const std::vector<Field<IoConfig>>& ioFields() {
  using I = IoConfig;
  static const std::vector<Field<I>> fields = {
      intField<I>({"id"}, true, &I::id, {0, 127, "(bus id)"}),
      intField<I>({"type"}, false, &I::type, kMesh),
      intField<I>({"rl0_init_state"}, false, &I::rl0_init_state, {0, 1, "(off, on)"}),
      intField<I>({"rl1_init_state"}, false, &I::rl1_init_state, {0, 1, "(off, on)"}),
  };
  return fields;
}

/// Reads a map of named modules (pipes, corners, ...). An absent or empty ({ }, null) group is no modules.
template <typename T>
std::vector<T> readGroup(const YAML::Node& root, const std::string& group, const std::vector<Field<T>>& fields,
                         const std::string& source, std::vector<std::string>& warnings) {
  std::vector<T> out;
  const YAML::Node node = root[group];
  if (!node.IsDefined() || node.IsNull()) return out;
  if (!node.IsMap()) throw ConfigError(source, group, "expected a map of modules, e.g. { name: {...}, }");
  if (node.size() > kMaxModulesPerGroup) {
    throw ConfigError(source, group,
                      "has " + std::to_string(node.size()) + " modules, more than " +
                          std::to_string(kMaxModulesPerGroup) + " (a robot file of a real robot has a few)");
  }
  for (const auto& kv : node) {
    T module;
    module.name = kv.first.Scalar();
    readFields(module, kv.second, fields, ScalarReader(source, group + "." + module.name), warnings);
    out.push_back(module);
  }
  return out;
}

/// Parses the N of "driveN"; -1 if the name is not of that form.
int numberedName(const std::string& name, const std::string& prefix) {
  if (name.size() <= prefix.size() || name.compare(0, prefix.size(), prefix) != 0) return -1;
  int n = 0;
  for (size_t i = prefix.size(); i < name.size(); ++i) {
    if (name[i] < '0' || name[i] > '9' || n > 100000) return -1;
    n = n * 10 + (name[i] - '0');
  }
  return n;
}

std::vector<DriveConfig> readDrives(const YAML::Node& root, const std::string& source,
                                    std::vector<std::string>& warnings) {
  const YAML::Node node = root["motor_drives"];
  if (!node.IsDefined()) throw ConfigError(source, "motor_drives", "is required (a map drive0, ...)");
  if (node.IsNull() || (node.IsMap() && node.size() == 0)) {
    throw ConfigError(source, "motor_drives", "is empty: a robot needs at least drive0 { node, x, y, r_wheel, ... }");
  }
  if (!node.IsMap()) {
    throw ConfigError(source, "motor_drives",
                      std::string("is a ") + (node.IsSequence() ? "list" : "single value") +
                          ", expected a map { drive0: {...}, drive1: {...}, }");
  }
  if (node.size() > kMaxDrives) {
    throw ConfigError(source, "motor_drives",
                      "has " + std::to_string(node.size()) + " drives, more than " + std::to_string(kMaxDrives));
  }
  std::map<int, DriveConfig> by_index;
  for (const auto& kv : node) {
    const std::string name = kv.first.Scalar();
    const int index = numberedName(name, "drive");
    if (index < 0) throw ConfigError(source, "motor_drives." + name, "expected a module named driveN (N = 0, 1, ...)");
    if (by_index.count(index))
      throw ConfigError(source, "motor_drives." + name, "drive number " + std::to_string(index) + " is given twice");
    DriveConfig drive;
    drive.index = index;
    const std::string where = "motor_drives." + name;
    readFields<DriveConfig>(drive, kv.second, driveFields(), ScalarReader(source, where), warnings, driveKeyRequired);
    validateDrive(drive, source, where);
    by_index[index] = drive;
  }
  std::vector<DriveConfig> drives;
  for (const auto& [index, drive] : by_index) {
    if (index != static_cast<int>(drives.size())) {
      std::string found;
      for (const auto& kv : by_index) found += (found.empty() ? "drive" : ", drive") + std::to_string(kv.first);
      throw ConfigError(source, "motor_drives",
                        "drives must be numbered from drive0 without gaps; drive" + std::to_string(drives.size()) +
                            " is missing (found " + found +
                            "; a drive name written twice in a file keeps only its last entry once loaded)");
    }
    drives.push_back(drive);
  }
  return drives;
}

/// The path of a `ros__parameters` map within the first two levels ("base_driver/ros__parameters"), or "".
std::string findRos2Parameters(const YAML::Node& root) {
  for (const auto& kv : root) {
    if (kv.first.Scalar() == "ros__parameters") return "ros__parameters";
    if (!kv.second.IsMap()) continue;
    for (const auto& inner : kv.second) {
      if (inner.first.Scalar() == "ros__parameters") return kv.first.Scalar() + "/ros__parameters";
    }
  }
  return "";
}

std::string normalisePluginName(const std::string& name) {
  // A commented example in field files writes "pltf_clc_std:PltfClcStd"; it means the same plugin.
  const auto pos = name.find(':');
  if (pos != std::string::npos && name.compare(pos, 2, "::") != 0) {
    return name.substr(0, pos) + "::" + name.substr(pos + 1);
  }
  return name;
}

}  // namespace

std::string nearestRobotFileGroup(const std::string& key) {
  static const std::vector<std::string> groups = {
      "base_calculator", "motor_drives", "batteries",      "pipes", "corners",
      "beams",           "casters",      "passive_wheels", "io",    "implement_can_ids"};
  std::string best;
  size_t best_distance = 3;  // at most two edits: a missing plural s, a swapped or missing letter
  for (const auto& g : groups) {
    const size_t distance = thorvald_common::editDistance(key, g);
    const size_t limit = g.size() <= 3 ? 0 : 2;  // "io" only exactly
    if (distance <= limit && distance < best_distance) {
      best_distance = distance;
      best = g;
    }
  }
  return best;
}

namespace {

std::vector<int> readImplementCanIds(const YAML::Node& root, const std::string& source) {
  std::vector<int> ids;
  const YAML::Node list = root["implement_can_ids"];
  if (!list.IsDefined() || list.IsNull()) return ids;
  if (!list.IsSequence()) {
    throw ConfigError(source, "implement_can_ids", "expected a list of 11-bit CAN ids, e.g. [0x181, 0x201]");
  }
  if (list.size() > kMaxModulesPerGroup) {
    throw ConfigError(source, "implement_can_ids",
                      "lists " + std::to_string(list.size()) + " ids, at most " + std::to_string(kMaxModulesPerGroup) +
                          " are accepted");
  }
  const ScalarReader reader(source, "implement_can_ids");
  for (size_t i = 0; i < list.size(); ++i) ids.push_back(reader.integer(list[i], std::to_string(i)));
  validateImplementCanIds(ids, source, "implement_can_ids");
  return ids;
}

}  // namespace

RobotConfig parseRobotConfig(const YAML::Node& root, const std::string& source) {
  RobotConfig config;
  config.source = source;
  if (!root.IsDefined() || root.IsNull()) {
    throw ConfigError(source, "<top level>", "is empty: expected a map of module groups (motor_drives, ...)");
  }
  if (!root.IsMap()) {
    throw ConfigError(source, "<top level>",
                      std::string("is a ") + (root.IsSequence() ? "list" : "single value") +
                          ", expected a map of module groups (base_calculator, motor_drives, batteries, ...)");
  }
  if (!root["motor_drives"].IsDefined()) {
    const std::string ros2 = findRos2Parameters(root);
    if (!ros2.empty()) {
      throw ConfigError(source, "<top level>",
                        "is a ROS 2 parameters file (node: ros__parameters: ...); the robot file is its sub-tree '" +
                            ros2 + "': load that sub-tree (its motor_drives, batteries, ...) instead");
    }
  }
  for (const auto& kv : root) {
    const std::string near = nearestRobotFileGroup(kv.first.Scalar());
    if (near == kv.first.Scalar()) continue;
    config.warnings.push_back(source + ": " + kv.first.Scalar() + ": unknown top-level key, ignored" +
                              (near.empty() ? "" : " (did you mean '" + near + "'?)"));
  }
  config.base_calculator = kDefaultBaseCalculator;
  if (root["base_calculator"].IsDefined() && !root["base_calculator"].IsNull()) {
    config.base_calculator =
        normalisePluginName(ScalarReader(source, "").text(root["base_calculator"], "base_calculator"));
  }
  config.drives = readDrives(root, source, config.warnings);
  config.batteries = readGroup(root, "batteries", batteryFields(), source, config.warnings);
  config.pipes = readGroup(root, "pipes", pipeFields(), source, config.warnings);
  config.corners = readGroup(root, "corners", cornerFields(), source, config.warnings);
  config.beams = readGroup(root, "beams", beamFields(), source, config.warnings);
  config.casters = readGroup(root, "casters", passiveWheelFields(), source, config.warnings);
  config.passive_wheels = readGroup(root, "passive_wheels", passiveWheelFields(), source, config.warnings);
  config.io = readGroup(root, "io", ioFields(), source, config.warnings);
  config.implement_can_ids = readImplementCanIds(root, source);
  validateCanNodeIds(config.drives, source);
  validateDriveSpacing(config.drives, source);
  for (const auto& beam : config.beams) {
    for (const auto& end : {beam.start, beam.end}) {
      const int index = numberedName(end, "drive");
      if (index < 0 || index >= static_cast<int>(config.drives.size())) {
        throw ConfigError(source, "beams." + beam.name, "joins '" + end + "', which is not a drive of this robot");
      }
    }
  }
  return config;
}

RobotConfig loadRobotConfigFile(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw ConfigError(path, "<file>", "cannot be read");
  } catch (const YAML::Exception& e) {
    throw ConfigError(path, "line " + std::to_string(e.mark.line + 1), std::string("not valid YAML: ") + e.msg);
  }
  return parseRobotConfig(root, path);
}

}  // namespace thorvald_base