#include "thorvald_sim/sensor_config.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <set>

namespace thorvald_sim {

Eigen::Matrix3d SensorConfig::mountRotation() const {
  return (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

namespace {

struct Reader {
  const YAML::Node& node;
  std::string where;
  std::set<std::string> used;

  [[noreturn]] void fail(const std::string& key, const std::string& expected) const {
    throw SensorConfigError(where + "." + key + ": expected " + expected);
  }
  double number(const std::string& key, double def, double lo, double hi) {
    used.insert(key);
    if (!node[key]) return def;
    double v;
    try {
      v = node[key].as<double>();
    } catch (const YAML::Exception&) {
      fail(key, "a number");
    }
    if (!std::isfinite(v) || v < lo || v > hi)
      fail(key, "a number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " + std::to_string(v));
    return v;
  }
  int integer(const std::string& key, int def, int lo, int hi) {
    const double v = number(key, def, lo, hi);
    if (v != std::floor(v)) fail(key, "a whole number");
    return static_cast<int>(v);
  }
  std::string text(const std::string& key, const std::string& def) {
    used.insert(key);
    if (!node[key]) return def;
    if (!node[key].IsScalar()) fail(key, "a string");
    return node[key].as<std::string>();
  }
  bool flag(const std::string& key, bool def) {
    used.insert(key);
    if (!node[key]) return def;
    try {
      return node[key].as<bool>();
    } catch (const YAML::Exception&) {
      fail(key, "true or false");
    }
  }
  Eigen::Vector3d vec3(const std::string& key) {
    used.insert(key);
    if (!node[key]) return Eigen::Vector3d::Zero();
    if (!node[key].IsSequence() || node[key].size() != 3) fail(key, "a list of three numbers");
    Eigen::Vector3d v;
    for (int i = 0; i < 3; ++i) {
      try {
        v[i] = node[key][i].as<double>();
      } catch (const YAML::Exception&) {
        fail(key, "a list of three numbers");
      }
      if (!std::isfinite(v[i])) fail(key, "finite numbers");
    }
    return v;
  }
  void checkUnknown() const {
    for (const auto& kv : node) {
      const std::string k = kv.first.as<std::string>();
      if (!used.count(k)) fail(k, "no such key (a misspelt key would silently change the sensor)");
    }
  }
};

/// The `realism` key of `r`'s node (a sensor's, or the file's), `def` when absent; an unknown profile is refused.
Realism readRealism(Reader& r, Realism def) {
  const std::string name = r.text("realism", realismName(def));
  const auto realism = realismFromName(name);
  if (!realism) r.fail("realism", "ideal or datasheet, got '" + name + "'");
  return *realism;
}

/// A device's datasheet model keys under `model:`: each overrides one figure of the device's table.
struct ModelKey {
  std::string key;
  double lo, hi;
};

/// Reads the keys of `table` from the `model` map of the sensor into `fields` (same order), strictly.
void readModelKeys(const YAML::Node& n, const std::string& where, const std::vector<ModelKey>& table,
                   const std::vector<double*>& fields, std::string* text_key = nullptr, const char* text_name = "") {
  if (!n["model"]) return;
  if (!n["model"].IsMap()) throw SensorConfigError(where + ".model: expected a map of model keys");
  Reader m{n["model"], where + ".model", {}};
  for (size_t i = 0; i < table.size(); ++i) *fields[i] = m.number(table[i].key, *fields[i], table[i].lo, table[i].hi);
  if (text_key) *text_key = m.text(text_name, *text_key);
  m.checkUnknown();
}

/// The datasheet model of the sensor's `device` (refused if it is not one of that type's), with `model:` overrides.
void readDatasheet(const YAML::Node& n, Reader& r, SensorConfig& c) {
  auto device = [&](const std::string& def, const std::vector<std::string>& known) {
    const std::string d = r.text("device", def);
    std::string list;
    for (const auto& k : known) list += (list.empty() ? "" : " or ") + k;
    if (std::find(known.begin(), known.end(), d) == known.end()) r.fail("device", list + ", got '" + d + "'");
    return d;
  };
  r.used.insert("model");
  switch (c.type) {
    case SensorType::kLidar: {
      device("utm_30lx", {"utm_30lx"});
      auto& m = c.lidar.model;
      readModelKeys(n, r.where,
                    {{"sigma_near", 0, 1},
                     {"sigma_far", 0, 1},
                     {"near_limit", 0, 1000},
                     {"max_incidence", 0, M_PI / 2},
                     {"dropout", 0, 1},
                     {"edge_jump", 0, 100},
                     {"mixed_probability", 0, 1},
                     {"sweep_time", 0, 1},
                     {"white_range", 0.1, 1000},
                     {"reflectance", 0, 10}},
                    {&m.sigma_near_m, &m.sigma_far_m, &m.near_limit_m, &m.max_incidence_rad, &m.dropout, &m.edge_jump_m,
                     &m.mixed_probability, &m.sweep_s, &m.white_range_m, &m.reflectance});
      break;
    }
    case SensorType::kUltrasonic: {
      device("generic", {"generic"});
      readModelKeys(n, r.where, {{"max_incidence", 0, M_PI / 2}}, {&c.ultrasonic.model.max_incidence_rad});
      break;
    }
    case SensorType::kDepthCamera: {
      device("d400", {"d400"});
      auto& m = c.depth.stereo;
      readModelKeys(n, r.where,
                    {{"noise_coeff", 0, 1},
                     {"baseline", 0, 1},
                     {"range_min", 0, 100},
                     {"dropout", 0, 1},
                     {"edge_jump", 0, 10},
                     {"flying_probability", 0, 1},
                     {"shiny_band", 0, M_PI / 2}},
                    {&m.noise_coeff, &m.baseline_m, &m.range_min_m, &m.dropout, &m.edge_jump, &m.flying_probability,
                     &m.shiny_band_rad},
                    &m.shiny_prefix, "shiny_prefix");
      break;
    }
    case SensorType::kImu: {
      const std::string d = device("um7", {"um7", "phidget_1044"});
      auto& m = c.imu.model;
      m = d == "um7" ? um7ImuModel() : phidget1044ImuModel();
      std::vector<ModelKey> table;
      std::vector<double*> fields;
      for (auto* t : {&m.gyro, &m.accel}) {
        const std::string p = t == &m.gyro ? "gyro_" : "accel_";
        table.insert(table.end(), {{p + "white", 0, 10},
                                   {p + "bias_instability", 0, 10},
                                   {p + "bias_correlation", 1e-3, 1e7},
                                   {p + "bias_random_walk", 0, 10},
                                   {p + "scale_factor", 0, 1}});
        fields.insert(fields.end(), {&t->white_sigma, &t->bias_instability, &t->bias_correlation_s,
                                     &t->bias_random_walk, &t->scale_factor_sigma});
      }
      readModelKeys(n, r.where, table, fields);
      break;
    }
  }
}

SensorConfig parseOne(const YAML::Node& n, const std::string& where, Realism file_realism) {
  if (!n.IsMap()) throw SensorConfigError(where + ": expected a map of sensor keys");
  Reader r{n, where, {}};
  SensorConfig c;
  static const std::map<std::string, SensorType> types = {{"lidar", SensorType::kLidar},
                                                          {"ultrasonic", SensorType::kUltrasonic},
                                                          {"depth_camera", SensorType::kDepthCamera},
                                                          {"imu", SensorType::kImu}};
  const std::string type = r.text("type", "");
  if (!types.count(type)) r.fail("type", "lidar, ultrasonic, depth_camera or imu");
  c.type = types.at(type);
  c.name = r.text("name", "");
  if (c.name.empty()) r.fail("name", "a sensor name");
  r.where = where + "(" + c.name + ")";
  c.parent = r.text("parent", "base_link");
  c.xyz = r.vec3("xyz");
  c.rpy = r.vec3("rpy");
  c.rate_hz = r.number("rate", c.rate_hz, 0.1, 1000.0);
  c.seed = static_cast<unsigned>(r.integer("seed", 1, 0, 1 << 30));
  c.realism = readRealism(r, file_realism);
  switch (c.type) {
    case SensorType::kLidar: {
      auto& s = c.lidar;
      c.topic = r.text("topic", "scan");
      s.angle_min_rad = r.number("angle_min", s.angle_min_rad, -M_PI, M_PI);
      s.angle_max_rad = r.number("angle_max", s.angle_max_rad, s.angle_min_rad, M_PI);
      s.samples = r.integer("samples", s.samples, 1, 100000);
      s.range_min_m = r.number("range_min", s.range_min_m, 0.0, 1000.0);
      s.range_max_m = r.number("range_max", s.range_max_m, s.range_min_m, 1000.0);
      s.noise_m = r.number("noise", s.noise_m, 0.0, 10.0);
      break;
    }
    case SensorType::kUltrasonic: {
      auto& s = c.ultrasonic;
      c.topic = r.text("topic", "ultrasonic/" + c.name);
      s.fov_rad = r.number("fov", s.fov_rad, 0.0, 3.0);
      s.range_min_m = r.number("range_min", s.range_min_m, 0.0, 100.0);
      s.range_max_m = r.number("range_max", s.range_max_m, s.range_min_m, 100.0);
      s.noise_m = r.number("noise", s.noise_m, 0.0, 1.0);
      s.rings = r.integer("rings", s.rings, 0, 20);
      s.rays_per_ring = r.integer("rays_per_ring", s.rays_per_ring, 1, 100);
      break;
    }
    case SensorType::kDepthCamera: {
      auto& s = c.depth;
      c.topic = r.text("topic", "camera");
      s.width = r.integer("width", s.width, 1, 4096);
      s.height = r.integer("height", s.height, 1, 4096);
      s.hfov_rad = r.number("hfov", s.hfov_rad, 0.01, 3.0);
      s.focal_px = r.number("fx", 0.0, 1.0, 1e5);  // a calibrated camera: fx = fy, principal point
      s.cx_px = r.number("cx", -1.0, 0.0, s.width - 1.0);
      s.cy_px = r.number("cy", -1.0, 0.0, s.height - 1.0);
      s.range_min_m = r.number("range_min", s.range_min_m, 0.0, 100.0);
      s.range_max_m = r.number("range_max", s.range_max_m, s.range_min_m, 100.0);
      s.noise_coeff = r.number("noise_coeff", s.noise_coeff, 0.0, 1.0);
      s.dropout = r.number("dropout", s.dropout, 0.0, 1.0);
      s.grazing_limit_rad = r.number("grazing_limit", s.grazing_limit_rad, 0.0, M_PI / 2);
      c.color = r.flag("color", false);
      break;
    }
    case SensorType::kImu: {
      c.topic = r.text("topic", "imu");
      c.imu.accel_noise_mps2 = r.number("accel_noise", c.imu.accel_noise_mps2, 0.0, 100.0);
      c.imu.gyro_noise_radps = r.number("gyro_noise", c.imu.gyro_noise_radps, 0.0, 100.0);
      break;
    }
  }
  c.lidar.realism = c.ultrasonic.realism = c.depth.realism = c.imu.realism = c.realism;
  readDatasheet(n, r, c);
  r.checkUnknown();
  return c;
}

}  // namespace

std::vector<SensorConfig> parseSensorConfig(const YAML::Node& root, const std::string& source) {
  std::vector<SensorConfig> out;
  if (!root || root.IsNull()) return out;
  const YAML::Node list = root.IsMap() ? root["sensors"] : root;
  Realism realism = Realism::kIdeal;
  if (root.IsMap() && root["realism"]) {  // the file's profile, for every sensor without its own
    const YAML::Node n = root["realism"];
    const auto r = n.IsScalar() ? realismFromName(n.as<std::string>()) : std::nullopt;
    if (!r)
      throw SensorConfigError(source + ": realism: expected ideal or datasheet, got '" +
                              (n.IsScalar() ? n.as<std::string>() : std::string("a non-string")) + "'");
    realism = *r;
  }
  if (!list || list.IsNull()) return out;
  if (!list.IsSequence()) throw SensorConfigError(source + ": sensors: expected a list of sensors");
  std::set<std::string> names;
  for (size_t i = 0; i < list.size(); ++i) {
    out.push_back(parseOne(list[i], source + ": sensors[" + std::to_string(i) + "]", realism));
    if (!names.insert(out.back().name).second)
      throw SensorConfigError(source + ": sensors[" + std::to_string(i) + "].name: '" + out.back().name +
                              "' is used twice; expected unique names");
  }
  return out;
}

std::vector<SensorConfig> loadSensorConfigFile(const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    throw SensorConfigError(path + ": cannot read the sensor file: " + e.what());
  }
  return parseSensorConfig(root, path);
}

}  // namespace thorvald_sim
