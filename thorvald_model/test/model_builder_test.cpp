#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>

#include "thorvald_model/model_builder.h"

using thorvald_base::ConfigError;
using thorvald_base::RobotConfig;
using thorvald_model::buildModel;
using thorvald_model::ModelOptions;
using thorvald_model::UrdfTree;

namespace {

const char* kRobot = R"(
motor_drives: {
  drive0: {node: 1, x: -0.6, y: -0.3, r_wheel: 0.2, prp_gr_rt: 42, prp_enc_ppr: 1024, prp_max_rpm: 3000,
           str_gr_rt: 42.86, str_enc_ppr: 1024, str_lim: 3.0},
  drive1: {node: 2, x: 0.6, y: -0.3, leg_mesh: 3, r_wheel: 0.25, w_wheel: 0.1, prp_gr_rt: 42, prp_enc_ppr: 1024,
           prp_max_rpm: 3000, str_gr_rt: 42.86, str_enc_ppr: 1024, str_lim: 2.5},
  drive2: {node: 3, x: 0.0, y: 0.3, type: 1, r_wheel: 0.2, prp_gr_rt: 42, prp_enc_ppr: 1024, prp_max_rpm: 3000},
}
batteries: { bat0: {id: 0, type: 1, x: 0.0, y: 0.0, z: 0.5, yaw: 1.5708} }
pipes: { p0: {x1: -0.6, y1: -0.3, x2: 0.6, y2: -0.3, height: 0.8, space: 0.1} }
corners: { c0: {type: 0, x: 0.6, y: 0.3, z: 0.8} }
beams: { b0: {start: drive0, end: drive1} }
casters: { zc: {x: -0.8, y: 0.3, z_top: 0.3, r_wheel: 0.1, w_wheel: 0.05, offset: 0.05},
           ac: {x: -0.8, y: -0.3, z_top: 0.3, r_wheel: 0.1, w_wheel: 0.05} }
passive_wheels: { pw: {x: 0.8, y: 0.0, z_top: 0.2, r_wheel: 0.1, w_wheel: 0.05} }
)";

RobotConfig parse(const std::string& text) { return thorvald_base::parseRobotConfig(YAML::Load(text), "test"); }

/// Position of a link's origin in base_link, walking joints up to the root (joint rotations are yaw-only or none
/// on the chains checked here, so adding offsets is exact for them).
Eigen::Vector3d originInBase(const UrdfTree& tree, const std::string& link) {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  std::string current = link;
  for (int guard = 0; guard < 20; ++guard) {
    const auto it =
        std::find_if(tree.joints.begin(), tree.joints.end(), [&](const auto& j) { return j.child == current; });
    if (it == tree.joints.end()) return p;
    p += it->xyz_m;
    current = it->parent;
  }
  ADD_FAILURE() << "loop in the tree at " << link;
  return p;
}

}  // namespace

TEST(ModelBuilder, DriveJointsAndWheelsFollowTheContract) {
  const UrdfTree tree = buildModel(parse(kRobot), ModelOptions{});
  for (int i : {0, 1}) {
    const auto* s = tree.findJoint("steering" + std::to_string(i));
    ASSERT_NE(s, nullptr);
    EXPECT_EQ(s->type, "revolute");
    EXPECT_EQ(s->parent, "base_link");
    EXPECT_TRUE(s->axis.isApprox(Eigen::Vector3d::UnitZ()));
  }
  EXPECT_DOUBLE_EQ(tree.findJoint("steering0")->upper_rad, 3.0);
  EXPECT_DOUBLE_EQ(tree.findJoint("steering1")->lower_rad, -2.5);
  EXPECT_EQ(tree.findJoint("steering2"), nullptr) << "a type-1 drive has no steering";
  const double radius[] = {0.2, 0.25, 0.2};
  const double xy[][2] = {{-0.6, -0.3}, {0.6, -0.3}, {0.0, 0.3}};
  for (int i = 0; i < 3; ++i) {
    const auto* w = tree.findJoint("wheel" + std::to_string(i));
    ASSERT_NE(w, nullptr);
    EXPECT_EQ(w->type, "continuous");
    EXPECT_TRUE(w->axis.isApprox(Eigen::Vector3d::UnitY()));
    EXPECT_EQ(w->child, "wheel_link" + std::to_string(i));
    const Eigen::Vector3d centre = originInBase(tree, w->child);
    EXPECT_NEAR(centre.z(), radius[i], 1e-12) << "wheel " << i << " must touch z = 0";
    EXPECT_NEAR(centre.x(), xy[i][0], 1e-12);
    EXPECT_NEAR(centre.y(), xy[i][1], 1e-12);
    const auto& shape = tree.findLink(w->child)->shapes.at(0);
    EXPECT_DOUBLE_EQ(shape.radius_m, radius[i]);
  }
  EXPECT_DOUBLE_EQ(tree.findLink("wheel_link1")->shapes.at(0).length_m, 0.1);
  EXPECT_DOUBLE_EQ(tree.findLink("wheel_link0")->shapes.at(0).length_m, 0.16) << "w_wheel default";
}

TEST(ModelBuilder, ModuleMassesArePlausible) {
  const UrdfTree tree = buildModel(parse(kRobot), ModelOptions{});
  const double steered = tree.findLink("steering_module_link0")->inertial.mass_kg +
                         tree.findLink("leg_link0")->inertial.mass_kg + tree.findLink("wheel_link0")->inertial.mass_kg;
  EXPECT_GT(steered, 20.0);
  EXPECT_LT(steered, 25.0);
  EXPECT_NEAR(tree.findLink("wheel_link0")->inertial.mass_kg, 4.0, 1e-9);
  EXPECT_NEAR(tree.findLink("battery_bat0")->inertial.mass_kg, 25.0, 1e-9);
  // Two 1.2 m tubes of 48 x 3 mm aluminium: 2 * 1.2 * 2700 * pi * (0.024^2 - 0.021^2).
  EXPECT_NEAR(tree.findLink("pipe_p0")->inertial.mass_kg, 2 * 1.2 * 2700 * M_PI * (0.024 * 0.024 - 0.021 * 0.021),
              1e-9);
  for (const auto& l : tree.links) {
    if (l.name == "base_link") continue;
    EXPECT_GT(l.inertial.mass_kg, 0.0) << l.name;
    const Eigen::Vector3d d = l.inertial.inertia.diagonal();
    EXPECT_GT(d.minCoeff(), 0.0) << l.name;
    EXPECT_LE(d.maxCoeff(), d.sum() - d.maxCoeff() + 1e-12) << l.name << ": triangle inequality";
  }
}

TEST(ModelBuilder, CastersAndPassiveWheelsSortedByName) {
  const UrdfTree tree = buildModel(parse(kRobot), ModelOptions{});
  // "ac" sorts before "zc": caster0 is at y = -0.3.
  const auto* swivel = tree.findJoint("caster0_swivel");
  ASSERT_NE(swivel, nullptr);
  EXPECT_EQ(swivel->type, "continuous");
  EXPECT_NEAR(swivel->xyz_m.y(), -0.3, 1e-12);
  EXPECT_NEAR(originInBase(tree, "caster_wheel_link1").z(), 0.1, 1e-12);
  EXPECT_NEAR(originInBase(tree, "caster_wheel_link1").x(), -0.85, 1e-12) << "trails by offset";
  ASSERT_NE(tree.findJoint("passive_wheel0"), nullptr);
  EXPECT_NEAR(originInBase(tree, "passive_wheel_link0").z(), 0.1, 1e-12);
  const auto names = thorvald_model::passiveJointNames(parse(kRobot), "");
  EXPECT_EQ(names, (std::vector<std::string>{"caster0_swivel", "caster0_wheel", "caster1_swivel", "caster1_wheel",
                                             "passive_wheel0"}));
}

TEST(ModelBuilder, MovableJointsOfARobotDescription) {
  const std::string urdf =
      "<robot name='r'><link name='a'/><link name='b'/><link name='c'/><link name='d'/>"
      "<joint name='fix' type='fixed'><parent link='a'/><child link='b'/></joint>"
      "<joint name='spin' type='continuous'><parent link='a'/><child link='c'/></joint>"
      "<joint name='lift' type='prismatic'><parent link='a'/><child link='d'/></joint>"
      "<joint name='float' type='floating'><parent link='c'/><child link='d'/></joint></robot>";
  EXPECT_EQ(thorvald_model::movableJointNames(urdf), (std::vector<std::string>{"spin", "lift"}));
  EXPECT_THROW(thorvald_model::movableJointNames("<robot"), std::runtime_error);
  EXPECT_THROW(thorvald_model::movableJointNames("<model/>"), std::runtime_error);
}

TEST(ModelBuilder, UnpublishedJointsAreThePassiveOnesAndTheDescriptionsOthers) {
  const RobotConfig config = parse(kRobot);
  const std::vector<std::string> passive = thorvald_model::passiveJointNames(config, "r1");
  EXPECT_EQ(thorvald_model::unpublishedJointNames(config, "r1", ""), passive) << "no robot_description";
  // A description with base_driver's joints, one passive joint, an extra joint (twice) and a fixed one: only the
  // extra joint is added, once, after the passive list.
  const std::string urdf =
      "<robot name='r'><link name='a'/><link name='b'/>"
      "<joint name='r1/wheel0' type='continuous'><parent link='a'/><child link='b'/></joint>"
      "<joint name='r1/steering1' type='revolute'><parent link='a'/><child link='b'/></joint>"
      "<joint name='r1/caster0_wheel' type='continuous'><parent link='a'/><child link='b'/></joint>"
      "<joint name='r1/rail_wheel' type='continuous'><parent link='a'/><child link='b'/></joint>"
      "<joint name='r1/rail_wheel' type='continuous'><parent link='a'/><child link='b'/></joint>"
      "<joint name='r1/mount' type='fixed'><parent link='a'/><child link='b'/></joint></robot>";
  std::vector<std::string> expected = passive;
  expected.push_back("r1/rail_wheel");
  EXPECT_EQ(thorvald_model::unpublishedJointNames(config, "r1", urdf), expected);
  EXPECT_THROW(thorvald_model::unpublishedJointNames(config, "r1", "<robot"), std::runtime_error);
}

TEST(ModelBuilder, PrefixReachesEveryName) {
  ModelOptions options;
  options.tf_prefix = "r7";
  const UrdfTree tree = buildModel(parse(kRobot), options);
  for (const auto& l : tree.links) EXPECT_EQ(l.name.rfind("r7/", 0), 0u) << l.name;
  for (const auto& j : tree.joints) {
    EXPECT_EQ(j.name.rfind("r7/", 0), 0u) << j.name;
    EXPECT_EQ(j.parent.rfind("r7/", 0), 0u) << j.parent;
  }
  EXPECT_EQ(thorvald_model::baseDriverJointNames(parse(kRobot), "r7"),
            (std::vector<std::string>{"r7/steering0", "r7/steering1", "r7/wheel0", "r7/wheel1", "r7/wheel2"}));
}

TEST(ModelBuilder, FloatingBaseAddsWorld) {
  ModelOptions options;
  options.floating_base = true;
  const UrdfTree tree = buildModel(parse(kRobot), options);
  EXPECT_EQ(tree.links.front().name, "world");
  EXPECT_EQ(tree.findJoint("world_to_base_link")->type, "floating");
}

namespace {
void expectError(const std::string& text, const std::string& where) {
  try {
    buildModel(parse(text), ModelOptions{});
    ADD_FAILURE() << "expected an error at " << where;
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.where(), where) << e.what();
  }
}
const char* kOneDrive =
    "motor_drives: {drive0: {node: 1, x: 0, y: 0, type: 1, r_wheel: 0.2, prp_gr_rt: 42, prp_enc_ppr: 1024, "
    "prp_max_rpm: 3000}}\n";
}  // namespace

TEST(ModelBuilder, ErrorsNameModuleAndKey) {
  expectError(std::string(kOneDrive) + "batteries: {bat0: {id: 0, type: 1, x: 0, y: 0, z: 0.05}}", "batteries.bat0.z");
  expectError(std::string(kOneDrive) + "pipes: {p: {x1: 0, y1: 0, x2: 1, y2: 0, height: 0.5, space: 0.6}}",
              "pipes.p.space");
  expectError(std::string(kOneDrive) + "pipes: {p: {x1: 0, y1: 0, x2: 1, y2: 0, height: 0, space: 0.1}}",
              "pipes.p.space");  // a lower tube below the ground
  expectError(std::string(kOneDrive) + "corners: {c: {x: 0, y: 0, z: 0}}", "corners.c.z");
  expectError(std::string(kOneDrive) + "casters: {c: {x: 0, y: 0, z_top: 0.3, r_wheel: 0.1, w_wheel: 0}}",
              "casters.c.w_wheel");
  expectError(
      "motor_drives: {drive0: {node: 1, x: 0, y: 0, type: 1, leg_mesh: 12, r_wheel: 0.2, prp_gr_rt: 42, "
      "prp_enc_ppr: 1024, prp_max_rpm: 3000}}\n",
      "motor_drives.drive0.leg_mesh");
}

TEST(ModelBuilder, PipeAtGroundHeightByDefault) {
  // docs/robot_file.md: height defaults to 0; given or left out, the pipe is built with its tube at z = 0.
  for (const std::string pipe : {"{x1: 0, y1: 0, x2: 1, y2: 0, height: 0}", "{x1: 0, y1: 0, x2: 1, y2: 0}"}) {
    const UrdfTree tree = buildModel(parse(std::string(kOneDrive) + "pipes: {p: " + pipe + "}"), ModelOptions{});
    ASSERT_NE(tree.findLink("pipe_p"), nullptr) << pipe;
    EXPECT_DOUBLE_EQ(originInBase(tree, "pipe_p").z(), 0.0) << pipe;
  }
}

TEST(ModelBuilder, LowCasterMountIsRaisedWithAWarning) {
  const UrdfTree tree = buildModel(
      parse(std::string(kOneDrive) + "casters: {c: {x: -0.5, y: 0, z_top: 0.1, r_wheel: 0.1, w_wheel: 0.05}}"),
      ModelOptions{});
  ASSERT_EQ(tree.warnings.size(), 1u);
  EXPECT_NE(tree.warnings[0].find("casters.c.z_top"), std::string::npos);
  EXPECT_NEAR(originInBase(tree, "caster_wheel_link0").z(), 0.1, 1e-12);
}
