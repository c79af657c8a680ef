// ekf_localization's parameters: a typical robot_localization YAML loads unchanged through the strict reader
// (every key read, the unimplemented ones named), and wrong values are refused. No master: the YAML is read into
// a map source.
#include <fstream>
#include <map>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "../src/nodes/ekf_settings.h"
#include "thorvald_navigation/fusion_ekf.h"

namespace tn = thorvald_navigation;

namespace {

XmlRpc::XmlRpcValue toXmlRpc(const YAML::Node& n) {
  if (n.IsSequence()) {
    XmlRpc::XmlRpcValue list;
    list.setSize(static_cast<int>(n.size()));
    for (std::size_t i = 0; i < n.size(); ++i) list[static_cast<int>(i)] = toXmlRpc(n[i]);
    return list;
  }
  const std::string s = n.as<std::string>();
  if (s == "true" || s == "false") return XmlRpc::XmlRpcValue(s == "true");
  // rosparam reads YAML 1.1, where an exponent without a decimal point (1e-9) is a string: keep it one here too.
  if (s.find_first_of("eE") != std::string::npos && s.find('.') == std::string::npos) return XmlRpc::XmlRpcValue(s);
  try {
    std::size_t used = 0;
    const int i = std::stoi(s, &used);
    if (used == s.size()) return XmlRpc::XmlRpcValue(i);
    const double d = std::stod(s, &used);
    if (used == s.size()) return XmlRpc::XmlRpcValue(d);
  } catch (const std::exception&) {
  }
  return XmlRpc::XmlRpcValue(s);
}

class MapSource : public thorvald_common::ParamSource {
 public:
  explicit MapSource(std::map<std::string, XmlRpc::XmlRpcValue> v) : v_(std::move(v)) {}
  bool get(const std::string& name, XmlRpc::XmlRpcValue& value) const override {
    const auto it = v_.find(name);
    if (it == v_.end()) return false;
    value = it->second;
    return true;
  }
  std::vector<std::string> names() const override {
    std::vector<std::string> out;
    for (const auto& kv : v_) out.push_back(kv.first);
    return out;
  }

 private:
  std::map<std::string, XmlRpc::XmlRpcValue> v_;
};

std::map<std::string, XmlRpc::XmlRpcValue> loadYaml(const std::string& file) {
  std::map<std::string, XmlRpc::XmlRpcValue> out;
  for (const auto& kv : YAML::LoadFile(file)) out[kv.first.as<std::string>()] = toXmlRpc(kv.second);
  return out;
}

const std::string kTypical = std::string(THORVALD_NAVIGATION_SOURCE_DIR) + "/test/data/robot_localization_ekf.yaml";

const tn::EkfInput& input(const tn::EkfSettings& s, const std::string& name) {
  for (const auto& in : s.inputs)
    if (in.name == name) return in;
  throw std::runtime_error("no input " + name);
}

}  // namespace

TEST(EkfSettings, TypicalRobotLocalizationFileLoadsUnchanged) {
  thorvald_common::ParamReader r(std::make_unique<MapSource>(loadYaml(kTypical)), "ekf_localization");
  const tn::EkfSettings s = tn::readEkfSettings(r);
  EXPECT_TRUE(r.unread().empty()) << r.unread().front();
  EXPECT_DOUBLE_EQ(s.frequency, 30.0);
  EXPECT_TRUE(s.two_d_mode);
  EXPECT_EQ(s.world_frame, "odom");
  ASSERT_EQ(s.inputs.size(), 6u);
  const tn::EkfInput& odom0 = input(s, "odom0");
  EXPECT_EQ(odom0.topic, "wheel/odometry");
  EXPECT_EQ(odom0.queue_size, 2);
  EXPECT_TRUE(odom0.config.use[tn::kFvx] && odom0.config.use[tn::kFvy] && odom0.config.use[tn::kFvyaw]);
  EXPECT_FALSE(odom0.config.use[tn::kFx]);
  EXPECT_DOUBLE_EQ(odom0.config.twist_gate, 1.0);
  EXPECT_FALSE(odom0.position_source());
  const tn::EkfInput& gps = input(s, "odom1");
  EXPECT_TRUE(gps.position_source());
  EXPECT_DOUBLE_EQ(gps.status_timeout_s, s.gps_timeout);
  EXPECT_DOUBLE_EQ(gps.config.pose_gate, 10.0);
  const tn::EkfInput& imu0 = input(s, "imu0");
  EXPECT_EQ(imu0.kind, tn::EkfInput::kImu);
  EXPECT_TRUE(imu0.config.remove_gravity);
  EXPECT_TRUE(imu0.config.relative);
  EXPECT_DOUBLE_EQ(imu0.config.angular_velocity_gate, 0.8);
  EXPECT_TRUE(imu0.config.use[tn::kFax]);
  const tn::EkfInput& imu1 = input(s, "imu1");
  EXPECT_TRUE(imu1.config.differential);
  EXPECT_DOUBLE_EQ(imu1.config.angular_velocity_gate, 3.0);
  EXPECT_TRUE(input(s, "pose0").config.differential);
  EXPECT_EQ(input(s, "twist0").kind, tn::EkfInput::kTwist);
  EXPECT_DOUBLE_EQ(s.process_noise(tn::kFyaw, tn::kFyaw), 0.06);
  EXPECT_DOUBLE_EQ(s.initial_covariance(tn::kFx, tn::kFx), 1e-9);  // written 1e-09: a string for rosparam
  EXPECT_DOUBLE_EQ(s.initial_covariance(tn::kFx, tn::kFy), 0.0);
  // The control input and the lagged-data smoothing are named in the one warning.
  const std::string w = tn::unsupportedWarning(s);
  for (const char* key : {"use_control", "control_config", "acceleration_limits", "smooth_lagged_data",
                          "dynamic_process_noise_covariance", "odom0_nodelay"})
    EXPECT_NE(w.find(key), std::string::npos) << key << " not in: " << w;
  EXPECT_EQ(w.find("odom0_config"), std::string::npos) << w;
}

TEST(EkfSettings, CottonRoverFileHasTheInProcessFusionsProcessNoise) {
  // config/cotton_rover_ekf.yaml: robot_localization's default process noise except x and y, 0.002 m^2/s as the
  // in-process RoverFusion (cotton_harvester_sim) runs it; at the default 0.05 the filter's sigma saws to 0.1 m
  // between 5 Hz fixes.
  thorvald_common::ParamReader r(std::make_unique<MapSource>(loadYaml(std::string(THORVALD_NAVIGATION_SOURCE_DIR) +
                                                                      "/config/cotton_rover_ekf.yaml")),
                                 "ekf_localization");
  const tn::EkfSettings s = tn::readEkfSettings(r);
  EXPECT_TRUE(r.unread().empty()) << r.unread().front();
  const tn::Cov15 d = tn::FusionEkf::defaultProcessNoise();
  for (int i = 0; i < tn::kFusionStates; ++i)
    for (int j = 0; j < tn::kFusionStates; ++j) {
      const double expected = i != j ? 0.0 : (i == tn::kFx || i == tn::kFy) ? 0.002 : d(i, i);
      EXPECT_DOUBLE_EQ(s.process_noise(i, j), expected) << tn::kFusionStateNames[i] << ", " << tn::kFusionStateNames[j];
    }
}

TEST(EkfSettings, UnknownKeyIsReportedUnread) {
  auto v = loadYaml(kTypical);
  v["odom0_confg"] = XmlRpc::XmlRpcValue(true);
  thorvald_common::ParamReader r(std::make_unique<MapSource>(v), "ekf_localization");
  tn::readEkfSettings(r);
  ASSERT_EQ(r.unread().size(), 1u);
  EXPECT_EQ(r.unread().front(), "odom0_confg");
}

TEST(EkfSettings, WrongValuesAreRefused) {
  auto load = [](std::map<std::string, XmlRpc::XmlRpcValue> v) {
    thorvald_common::ParamReader r(std::make_unique<MapSource>(std::move(v)), "ekf_localization");
    return tn::readEkfSettings(r);
  };
  auto typical = loadYaml(kTypical);
  XmlRpc::XmlRpcValue short_cfg;
  short_cfg.setSize(6);
  for (int i = 0; i < 6; ++i) short_cfg[i] = true;
  auto v = typical;
  v["odom0_config"] = short_cfg;
  EXPECT_THROW(load(v), thorvald_common::ParamError);
  v = typical;
  v["odom1_pose_rejection_threshold"] = XmlRpc::XmlRpcValue(-1.0);
  EXPECT_THROW(load(v), thorvald_common::ParamError);
  v = typical;
  XmlRpc::XmlRpcValue words;
  words.setSize(15);
  for (int i = 0; i < 15; ++i) words[i] = std::string(i == 3 ? "big" : "1e-9");
  v["initial_estimate_covariance"] = words;
  EXPECT_THROW(load(v), thorvald_common::ParamError);
  v = typical;
  v["world_frame"] = XmlRpc::XmlRpcValue(std::string("earth"));
  EXPECT_THROW(load(v), thorvald_common::ParamError);
  EXPECT_THROW(load({{"frequency", XmlRpc::XmlRpcValue(10.0)}}), thorvald_common::ParamError);  // no input
}

TEST(EkfSettings, MessageKindsCarryOnlyTheirEntries) {
  // An IMU cannot give a position: robot_localization ignores it; here it is named in the warning.
  XmlRpc::XmlRpcValue cfg;
  cfg.setSize(15);
  for (int i = 0; i < 15; ++i) cfg[i] = (i == 0 || i == 11);
  thorvald_common::ParamReader r(std::make_unique<MapSource>(std::map<std::string, XmlRpc::XmlRpcValue>{
                                     {"imu0", XmlRpc::XmlRpcValue(std::string("imu"))}, {"imu0_config", cfg}}),
                                 "ekf_localization");
  const tn::EkfSettings s = tn::readEkfSettings(r);
  EXPECT_FALSE(s.inputs[0].config.use[tn::kFx]);
  EXPECT_TRUE(s.inputs[0].config.use[tn::kFvyaw]);
  EXPECT_NE(tn::unsupportedWarning(s).find("imu0_config: x"), std::string::npos);
}
