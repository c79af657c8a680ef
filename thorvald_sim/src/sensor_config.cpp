#include "thorvald_sim/sensor_config.h"

#include <yaml-cpp/yaml.h>

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

SensorConfig parseOne(const YAML::Node& n, const std::string& where) {
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
  r.checkUnknown();
  return c;
}

}  // namespace

std::vector<SensorConfig> parseSensorConfig(const YAML::Node& root, const std::string& source) {
  std::vector<SensorConfig> out;
  if (!root || root.IsNull()) return out;
  const YAML::Node list = root.IsMap() ? root["sensors"] : root;
  if (!list || list.IsNull()) return out;
  if (!list.IsSequence()) throw SensorConfigError(source + ": sensors: expected a list of sensors");
  std::set<std::string> names;
  for (size_t i = 0; i < list.size(); ++i) {
    out.push_back(parseOne(list[i], source + ": sensors[" + std::to_string(i) + "]"));
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
