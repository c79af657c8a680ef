// The greenhouse robot's sensor frames in its URDF (thorvald_bringup's greenhouse_frame.urdf merged by thorvald_model's
// urdf_generator) are where thorvald_sim's sensor files mount the sensors: every sensor of sensors_greenhouse.yaml and
// sensors_greenhouse_datasheet.yaml (the rear range finders included) is a link under base_link at the same position
// (1 mm) and rotation (1 mrad). Fails when the URDF and the sensor files drift apart.
#include <gtest/gtest.h>
#include <tinyxml2.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <map>
#include <sstream>
#include <set>
#include <string>

#include "thorvald_sim/sensor_config.h"

namespace {

#if defined(URDF_GENERATOR) && defined(BRINGUP_CONFIG_DIR)
struct Mount {
  std::string parent;
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero();
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
};

Eigen::Vector3d triple(const char* text) {
  Eigen::Vector3d v = Eigen::Vector3d::Zero();
  if (text) std::istringstream(text) >> v.x() >> v.y() >> v.z();
  return v;
}

// The fixed joints of the generated URDF (no tf_prefix), by child link.
std::map<std::string, Mount> fixedMounts() {
  const std::string dir = BRINGUP_CONFIG_DIR;
  const std::string cmd = std::string(URDF_GENERATOR) + " --config '" + dir +
                          "/greenhouse_rail_robot.yaml' --extras '" + dir +
                          "/greenhouse_frame.urdf' --tf-prefix '' --robot-name greenhouse";
  std::string urdf;
  if (FILE* p = popen(cmd.c_str(), "r")) {
    char buf[4096];
    size_t n;
    while ((n = fread(buf, 1, sizeof(buf), p)) > 0) urdf.append(buf, n);
    if (pclose(p) != 0) urdf.clear();
  }
  std::map<std::string, Mount> mounts;
  tinyxml2::XMLDocument doc;
  if (urdf.empty() || doc.Parse(urdf.c_str(), urdf.size()) != tinyxml2::XML_SUCCESS) return mounts;
  const auto* robot = doc.FirstChildElement("robot");
  for (auto* j = robot ? robot->FirstChildElement("joint") : nullptr; j; j = j->NextSiblingElement("joint")) {
    const auto *parent = j->FirstChildElement("parent"), *child = j->FirstChildElement("child");
    if (!j->Attribute("type", "fixed") || !parent || !child || !child->Attribute("link")) continue;
    Mount m;
    m.parent = parent->Attribute("link") ? parent->Attribute("link") : "";
    if (const auto* o = j->FirstChildElement("origin")) {
      m.xyz = triple(o->Attribute("xyz"));
      const Eigen::Vector3d rpy = triple(o->Attribute("rpy"));
      m.rotation =
          (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
           Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
              .toRotationMatrix();
    }
    mounts[child->Attribute("link")] = m;
  }
  return mounts;
}

class GreenhouseSensorFrames : public testing::TestWithParam<std::string> {};

TEST_P(GreenhouseSensorFrames, UrdfLinksWhereTheSensorFileMountsTheSensors) {
  const auto mounts = fixedMounts();
  ASSERT_FALSE(mounts.empty()) << "urdf_generator gave no URDF";
  const auto sensors = thorvald_sim::loadSensorConfigFile(std::string(SIM_CONFIG_DIR) + "/" + GetParam());
  ASSERT_GE(sensors.size(), 9u);
  // The rear range finders greenhouse_rail_nav's uv_mission watches while reversing (its ~rear_sensors default).
  std::set<std::string> rear = {"rear_left", "rear_right", "rear_centre", "rear_left_corner", "rear_right_corner"};
  for (const auto& s : sensors) {
    SCOPED_TRACE(GetParam() + ": " + s.name);
    const auto it = mounts.find(s.name);
    ASSERT_NE(it, mounts.end()) << "no link " << s.name << " in greenhouse_frame.urdf";
    EXPECT_EQ(it->second.parent, s.parent);
    EXPECT_LT((it->second.xyz - s.xyz).norm(), 1e-3)
        << "URDF " << it->second.xyz.transpose() << ", sensor file " << s.xyz.transpose();
    const double angle = Eigen::AngleAxisd(it->second.rotation.transpose() * s.mountRotation()).angle();
    EXPECT_LT(angle, 1e-3) << "rotations differ by " << angle << " rad";
    rear.erase(s.name);
  }
  for (const auto& missing : rear) ADD_FAILURE() << "the sensor file lacks the rear range finder " << missing;
}

TEST(GreenhouseSensorFrames, CameraOpticalFrameLooksAlongTheCamera) {
  const auto mounts = fixedMounts();
  const auto it = mounts.find("camera_optical");
  ASSERT_NE(it, mounts.end());
  EXPECT_EQ(it->second.parent, "camera");
  // z along the camera's x (the optical axis), x along its -y (right), y along its -z (down)
  EXPECT_LT((it->second.rotation.col(2) - Eigen::Vector3d::UnitX()).norm(), 1e-3);
  EXPECT_LT((it->second.rotation.col(0) + Eigen::Vector3d::UnitY()).norm(), 1e-3);
  EXPECT_LT((it->second.rotation.col(1) + Eigen::Vector3d::UnitZ()).norm(), 1e-3);
}

INSTANTIATE_TEST_SUITE_P(SensorFiles, GreenhouseSensorFrames,
                         testing::Values("sensors_greenhouse.yaml", "sensors_greenhouse_datasheet.yaml"));
#endif

}  // namespace
