#include "thorvald_base/robot_config.h"

#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <set>

#include "module_fields.h"
#include "thorvald_base/angles.h"

namespace thorvald_base {
namespace {

using detail::Field;
using detail::intField;
using detail::numberField;
using detail::readFields;
using detail::ScalarReader;
using detail::textField;

const std::vector<Field<DriveConfig>>& driveFields() {
  using D = DriveConfig;
  static const std::vector<Field<D>> fields = {
      intField<D>({"node"}, true, &D::node),
      numberField<D>({"x"}, true, &D::x),
      numberField<D>({"y"}, true, &D::y),
      intField<D>({"type"}, false, &D::type),
      intField<D>({"leg_mesh"}, false, &D::leg_mesh),
      numberField<D>({"r_wheel"}, true, &D::r_wheel),
      numberField<D>({"w_wheel"}, false, &D::w_wheel),
      numberField<D>({"prp_gr_rt"}, true, &D::prp_gr_rt),
      numberField<D>({"prp_enc_ppr"}, true, &D::prp_enc_ppr),
      numberField<D>({"prp_max_rpm"}, true, &D::prp_max_rpm),
      numberField<D>({"prp_sim_a"}, false, &D::prp_sim_a),
      numberField<D>({"str_gr_rt"}, true, &D::str_gr_rt),
      numberField<D>({"str_enc_ppr"}, true, &D::str_enc_ppr),
      numberField<D>({"str_lim", "str_llm"}, true, &D::str_lim),
      numberField<D>({"str_sim_v", "str_stm_v"}, false, &D::str_sim_v),
      textField<D>({"protocol"}, false, &D::protocol),
  };
  return fields;
}

/// Steering keys are required only for steered (type-0) drives.
bool driveKeyRequired(const DriveConfig& d, const Field<DriveConfig>& f) {
  if (!f.required) return false;
  return d.steered() || f.names[0].rfind("str_", 0) != 0;
}

const std::vector<Field<BatteryConfig>>& batteryFields() {
  using B = BatteryConfig;
  static const std::vector<Field<B>> fields = {
      intField<B>({"id"}, false, &B::id),
      intField<B>({"type"}, false, &B::type),
      numberField<B>({"x"}, false, &B::x),
      numberField<B>({"y"}, false, &B::y),
      numberField<B>({"z"}, false, &B::z),
      numberField<B>({"yaw"}, false, &B::yaw),
      intField<B>({"bat_mesh"}, false, &B::bat_mesh),
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
      numberField<P>({"x1"}, true, &P::x1),          numberField<P>({"y1"}, true, &P::y1),
      numberField<P>({"x2"}, true, &P::x2),          numberField<P>({"y2"}, true, &P::y2),
      numberField<P>({"height"}, false, &P::height), numberField<P>({"space"}, false, &P::space),
  };
  return fields;
}

const std::vector<Field<CornerConfig>>& cornerFields() {
  using C = CornerConfig;
  static const std::vector<Field<C>> fields = {
      intField<C>({"type"}, false, &C::type),
      intField<C>({"corner_mesh"}, false, &C::corner_mesh),
      numberField<C>({"x"}, true, &C::x),
      numberField<C>({"y"}, true, &C::y),
      numberField<C>({"z"}, false, &C::z),
      numberField<C>({"space"}, false, &C::space),
      numberField<C>({"susp_ang"}, false, &C::susp_ang),
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
      numberField<W>({"x"}, true, &W::x),
      numberField<W>({"y"}, true, &W::y),
      numberField<W>({"z_top"}, false, &W::z_top),
      numberField<W>({"r_wheel"}, false, &W::r_wheel),
      numberField<W>({"w_wheel"}, false, &W::w_wheel),
      numberField<W>({"offset"}, false, &W::offset),
  };
  return fields;
}

const std::vector<Field<IoConfig>>& ioFields() {
  using I = IoConfig;
  static const std::vector<Field<I>> fields = {
      intField<I>({"id"}, true, &I::id),
      intField<I>({"type"}, false, &I::type),
      intField<I>({"rl0_init_state"}, false, &I::rl0_init_state),
      intField<I>({"rl1_init_state"}, false, &I::rl1_init_state),
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
  if (!node.IsDefined() || node.IsNull()) throw ConfigError(source, "motor_drives", "is required (a map drive0, ...)");
  if (!node.IsMap() || node.size() == 0) {
    throw ConfigError(source, "motor_drives", "expected a non-empty map { drive0: {...}, drive1: {...}, }");
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
      throw ConfigError(
          source, "motor_drives",
          "drives must be numbered from drive0 without gaps; drive" + std::to_string(drives.size()) + " is missing");
    }
    drives.push_back(drive);
  }
  return drives;
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

void validateDrive(const DriveConfig& d, const std::string& source, const std::string& where) {
  auto positive = [&](double v, const char* key) {
    if (!(v > 0.0)) throw ConfigError(source, where + "." + key, "must be greater than 0, found " + std::to_string(v));
  };
  if (d.type != 0 && d.type != 1) {
    throw ConfigError(source, where + ".type", "must be 0 (steering + propulsion) or 1 (propulsion only)");
  }
  if (d.node < 0 || d.node > 127) throw ConfigError(source, where + ".node", "must be a CAN node id 0..127");
  positive(d.r_wheel, "r_wheel");
  positive(d.w_wheel, "w_wheel");
  positive(d.prp_gr_rt, "prp_gr_rt");
  positive(d.prp_enc_ppr, "prp_enc_ppr");
  positive(d.prp_max_rpm, "prp_max_rpm");
  positive(d.prp_sim_a, "prp_sim_a");
  if (d.protocol != "thorvald" && d.protocol != "cia402") {
    throw ConfigError(source, where + ".protocol", "must be 'thorvald' or 'cia402', found '" + d.protocol + "'");
  }
  if (!d.steered()) return;
  positive(d.str_gr_rt, "str_gr_rt");
  positive(d.str_enc_ppr, "str_enc_ppr");
  positive(d.str_sim_v, "str_sim_v");
  if (!(d.str_lim > 0.0) || d.str_lim > kPi + 1e-9) {
    throw ConfigError(source, where + ".str_lim",
                      "must be in (0, pi] rad (the cable allows about +-176 deg), found " + std::to_string(d.str_lim));
  }
}

bool setDriveKey(DriveConfig& drive, const std::string& key, double value) {
  using D = DriveConfig;
  static const std::map<std::string, double D::*> keys = {
      {"x", &D::x},
      {"y", &D::y},
      {"r_wheel", &D::r_wheel},
      {"w_wheel", &D::w_wheel},
      {"prp_gr_rt", &D::prp_gr_rt},
      {"prp_enc_ppr", &D::prp_enc_ppr},
      {"prp_max_rpm", &D::prp_max_rpm},
      {"prp_sim_a", &D::prp_sim_a},
      {"str_gr_rt", &D::str_gr_rt},
      {"str_enc_ppr", &D::str_enc_ppr},
      {"str_lim", &D::str_lim},
      {"str_llm", &D::str_lim},
      {"str_sim_v", &D::str_sim_v},
      {"str_stm_v", &D::str_sim_v},
  };
  const auto it = keys.find(key);
  if (it == keys.end() || !std::isfinite(value)) return false;
  drive.*(it->second) = value;
  return true;
}

RobotConfig parseRobotConfig(const YAML::Node& root, const std::string& source) {
  RobotConfig config;
  config.source = source;
  if (!root.IsMap()) throw ConfigError(source, "<top level>", "expected a map of module groups");
  static const std::set<std::string> known = {"base_calculator", "motor_drives", "batteries",      "pipes", "corners",
                                              "beams",           "casters",      "passive_wheels", "io"};
  for (const auto& kv : root) {
    if (!known.count(kv.first.Scalar())) {
      config.warnings.push_back(source + ": " + kv.first.Scalar() + ": unknown top-level key, ignored");
    }
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
