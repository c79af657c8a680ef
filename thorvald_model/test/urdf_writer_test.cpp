#include <gtest/gtest.h>
#include <urdf_parser/urdf_parser.h>
#include <yaml-cpp/yaml.h>

#include "thorvald_model/model_builder.h"
#include "thorvald_model/urdf_writer.h"

using thorvald_model::FragmentError;
using thorvald_model::UrdfFragment;
using thorvald_model::WriteOptions;

namespace {

thorvald_model::UrdfTree fourWheels(const std::string& prefix) {
  const char* text = R"(
motor_drives: {
  drive0: {node: 1, x: -0.5, y: -0.3, r_wheel: 0.2, prp_gr_rt: 42, prp_enc_ppr: 1024, prp_max_rpm: 3000,
           str_gr_rt: 42.86, str_enc_ppr: 1024, str_lim: 3.0},
  drive1: {node: 2, x: 0.5, y: 0.3, r_wheel: 0.2, prp_gr_rt: 42, prp_enc_ppr: 1024, prp_max_rpm: 3000,
           str_gr_rt: 42.86, str_enc_ppr: 1024, str_lim: 3.0},
}
batteries: { bat0: {id: 0, x: 0.0, y: 0.0, z: 0.5, yaw: 0.3} }
)";
  thorvald_model::ModelOptions options;
  options.tf_prefix = prefix;
  return thorvald_model::buildModel(thorvald_base::parseRobotConfig(YAML::Load(text), "test"), options);
}

const char* kSensor = R"(<robot name="sensors">
  <link name="laser"><inertial><mass value="0.3"/><inertia ixx="1e-4" iyy="1e-4" izz="1e-4" ixy="0" ixz="0" iyz="0"/>
  </inertial></link>
  <joint name="laser_joint" type="fixed"><parent link="base_link"/><child link="laser"/>
    <origin xyz="0.6 0 1.0" rpy="0 0 0"/></joint>
</robot>)";

}  // namespace

TEST(UrdfWriter, UrdfdomReadsWhatWeWrite) {
  const auto tree = fourWheels("");
  const auto model = urdf::parseURDF(thorvald_model::writeUrdf(tree, {}, WriteOptions{}));
  ASSERT_TRUE(model);
  EXPECT_EQ(model->getRoot()->name, "base_link");
  EXPECT_EQ(model->links_.size(), tree.links.size());
  const auto steering = model->getJoint("steering0");
  ASSERT_TRUE(steering);
  EXPECT_EQ(steering->type, urdf::Joint::REVOLUTE);
  EXPECT_DOUBLE_EQ(steering->limits->upper, 3.0);
  EXPECT_EQ(model->getJoint("wheel1")->type, urdf::Joint::CONTINUOUS);
  double mass = 0.0;
  for (const auto& [name, link] : model->links_)
    if (link->inertial) mass += link->inertial->mass;
  EXPECT_NEAR(mass, tree.totalMassKg(), 1e-6);
  const auto battery = model->getJoint("battery_bat0_joint");
  double r, p, y;
  battery->parent_to_joint_origin_transform.rotation.getRPY(r, p, y);
  EXPECT_NEAR(y, 0.3, 1e-9);
}

TEST(UrdfWriter, FragmentAttachesToAGeneratedLinkUnderThePrefix) {
  WriteOptions options;
  options.tf_prefix = "robot_a";
  const auto model =
      urdf::parseURDF(thorvald_model::writeUrdf(fourWheels("robot_a"), {{"sensors.urdf", kSensor}}, options));
  ASSERT_TRUE(model);
  const auto laser = model->getLink("robot_a/laser");
  ASSERT_TRUE(laser);
  EXPECT_EQ(laser->getParent()->name, "robot_a/base_link");
  EXPECT_TRUE(model->getJoint("robot_a/laser_joint"));
}

TEST(UrdfWriter, MujocoCompilerBlockOnlyWhenAsked) {
  const auto tree = fourWheels("");
  EXPECT_EQ(thorvald_model::writeUrdf(tree, {}, WriteOptions{}).find("<mujoco>"), std::string::npos);
  WriteOptions options;
  options.mujoco_compiler = true;
  EXPECT_NE(thorvald_model::writeUrdf(tree, {}, options).find("fusestatic=\"false\""), std::string::npos);
}

namespace {
void expectFragmentError(const std::string& fragment, const std::string& message_part) {
  try {
    thorvald_model::writeUrdf(fourWheels(""), {{"bad.urdf", fragment}}, WriteOptions{});
    ADD_FAILURE() << "expected: " << message_part;
  } catch (const FragmentError& e) {
    EXPECT_NE(std::string(e.what()).find(message_part), std::string::npos) << e.what();
  }
}
}  // namespace

TEST(UrdfWriter, BrokenFragmentsAreRejectedWithTheReason) {
  expectFragmentError("<robot><link name='x'>", "bad.urdf: not readable XML");
  expectFragmentError("<model/>", "expected a <robot> element");
  expectFragmentError("<robot><link name='wheel_link0'/></robot>", "link 'wheel_link0' is defined twice");
  expectFragmentError(
      "<robot><link name='tool'/><joint name='t' type='fixed'><parent link='nowhere'/><child link='tool'/></joint>"
      "</robot>",
      "joint 't' names link 'nowhere'");
  expectFragmentError(
      "<robot><joint name='t' type='fixed'><parent link='base_link'/><child link='wheel_link0'/></joint></robot>",
      "link 'wheel_link0' has two parent joints");
  expectFragmentError("<robot><joint name='t' type='fixed'><child link='wheel_link0'/></joint></robot>",
                      "joint 't' has no <parent");
}
