#include <gmock/gmock.h>
#include <yaml-cpp/yaml.h>

#include "thorvald_base/robot_config.h"

using thorvald_base::ConfigError;
using thorvald_base::loadRobotConfigFile;
using thorvald_base::parseRobotConfig;
using thorvald_base::RobotConfig;

namespace {

const char* kDrive =
    "{node: 1, x: 0.5, y: -0.3, r_wheel: 0.2, prp_gr_rt: 42, prp_enc_ppr: 1024, prp_max_rpm: 3000, "
    "str_gr_rt: 42.86, str_enc_ppr: 1024, str_lim: 3.07}";

RobotConfig parse(const std::string& text) { return parseRobotConfig(YAML::Load(text), "test.yaml"); }

/// Expects a ConfigError whose location is `where` and whose text contains `what`.
void expectError(const std::string& text, const std::string& where, const std::string& what) {
  try {
    parse(text);
    FAIL() << "no error for: " << text;
  } catch (const ConfigError& e) {
    EXPECT_EQ(e.where(), where) << e.what();
    EXPECT_THAT(e.problem(), testing::HasSubstr(what)) << e.what();
    EXPECT_THAT(std::string(e.what()), testing::HasSubstr("test.yaml"));
  }
}

std::string withDrive0(const std::string& replace_from, const std::string& replace_to) {
  std::string d = kDrive;
  d.replace(d.find(replace_from), replace_from.size(), replace_to);
  return "motor_drives: {drive0: " + d + "}";
}

}  // namespace

TEST(RobotConfig, PaperFigure5Loads) {
  // The one copy of the Figure 5 robot file is thorvald_base/config/figure5.yaml (tests run in thorvald_base/test).
  const RobotConfig c = loadRobotConfigFile("../config/figure5.yaml");
  ASSERT_EQ(c.drives.size(), 4u);
  EXPECT_EQ(c.base_calculator, "pltf_clc_std::PltfClcStd");
  EXPECT_DOUBLE_EQ(c.drives[2].x, 0.547);
  EXPECT_DOUBLE_EQ(c.drives[2].y, 0.30);
  EXPECT_EQ(c.drives[3].node, 4);
  EXPECT_EQ(c.drives[3].leg_mesh, 3);
  EXPECT_DOUBLE_EQ(c.drives[0].str_lim, 3.078027759);  // written as str_llm
  EXPECT_DOUBLE_EQ(c.drives[0].str_sim_v, 4.0);        // written as str_stm_v
  EXPECT_DOUBLE_EQ(c.drives[0].w_wheel, 0.16);         // default
  EXPECT_TRUE(c.warnings.empty());
}

TEST(RobotConfig, FieldQuirksLoad) {
  const RobotConfig c = loadRobotConfigFile("data/field_quirks.yaml");
  EXPECT_EQ(c.base_calculator, "pltf_clc_2wdiff::PltfClc2WDiff");
  ASSERT_EQ(c.drives.size(), 2u);
  EXPECT_EQ(c.drives[0].node, 1);  // 1.0
  EXPECT_EQ(c.drives[0].type, 1);
  EXPECT_DOUBLE_EQ(c.drives[0].y, -0.35);  // "-0.35"
  EXPECT_DOUBLE_EQ(c.drives[0].prp_enc_ppr, 1024);
  ASSERT_EQ(c.batteries.size(), 2u);
  EXPECT_EQ(c.batteries[0].id, 1);  // node 345 - 344
  EXPECT_TRUE(c.batteries[0].present());
  EXPECT_FALSE(c.batteries[1].present());
  ASSERT_EQ(c.pipes.size(), 1u);
  EXPECT_DOUBLE_EQ(c.pipes[0].x1, -0.425);
  EXPECT_TRUE(c.corners.empty());
  ASSERT_EQ(c.casters.size(), 1u);
  EXPECT_DOUBLE_EQ(c.casters[0].r_wheel, 0.08);
  ASSERT_EQ(c.io.size(), 1u);
  EXPECT_EQ(c.io[0].rl1_init_state, 1);
  // Unknown keys are warned about, once each, and do not fail.
  ASSERT_EQ(c.warnings.size(), 2u);
  EXPECT_THAT(c.warnings, testing::Contains(testing::HasSubstr("motor_drives.drive0.future_key")));
  EXPECT_THAT(c.warnings, testing::Contains(testing::HasSubstr("lidar_mount")));
}

TEST(RobotConfig, SingleColonPluginNameMeansTheSamePlugin) {
  const RobotConfig c =
      parse(std::string("base_calculator: \"pltf_clc_std:PltfClcStd\"\nmotor_drives: {drive0: ") + kDrive + "}");
  EXPECT_EQ(c.base_calculator, "pltf_clc_std::PltfClcStd");
}

TEST(RobotConfig, PropulsionOnlyDrivesNeedNoSteeringKeys) {
  const RobotConfig c = parse(
      "motor_drives: {drive0: {node: 1, type: 1, x: 0, y: 0.3, r_wheel: 0.2, prp_gr_rt: 42, prp_enc_ppr: 1024, "
      "prp_max_rpm: 3000}}");
  EXPECT_FALSE(c.drives[0].steered());
}

TEST(RobotConfig, ErrorsNameTheKey) {
  expectError(withDrive0("r_wheel: 0.2", "r_wheel: -0.2"), "motor_drives.drive0.r_wheel",
              "outside its physical range [0.02, 1] m");
  expectError(withDrive0("prp_gr_rt: 42", "prp_gr_rt: 0"), "motor_drives.drive0.prp_gr_rt", "physical range");
  expectError(withDrive0("str_lim: 3.07", "str_lim: 3.5"), "motor_drives.drive0.str_lim", "[0.01, 3.1416] rad");
  expectError(withDrive0("r_wheel: 0.2, ", ""), "motor_drives.drive0.r_wheel", "required");
  expectError(withDrive0("x: 0.5", "x: abc"), "motor_drives.drive0.x", "finite number");
  expectError(withDrive0("x: 0.5", "x: .nan"), "motor_drives.drive0.x", "finite number");
  expectError(withDrive0("node: 1", "node: 1.5"), "motor_drives.drive0.node", "integer");
  expectError(withDrive0("x: 0.5", "x: [1, 2]"), "motor_drives.drive0.x", "number");
  expectError(withDrive0("node: 1", "node: 1, type: 2"), "motor_drives.drive0.type", "(0 steered, 1 fixed)");
  expectError(withDrive0("str_lim: 3.07", "str_lim: 3.07, str_llm: 3.0"), "motor_drives.drive0.str_llm", "given twice");
  expectError(std::string("motor_drives: {drive0: ") + kDrive + ", drive00: " + kDrive + "}", "motor_drives.drive00",
              "given twice");
  expectError(std::string("motor_drives: {drive0: ") + kDrive + ", drive2: " + kDrive + "}", "motor_drives",
              "drive1 is missing");
  expectError(std::string("motor_drives: {wheel0: ") + kDrive + "}", "motor_drives.wheel0", "driveN");
  expectError("batteries: {}", "motor_drives", "required");
  expectError("motor_drives: { }", "motor_drives", "is empty");
  expectError(std::string("motor_drives: {drive0: ") + kDrive + "}\nbeams: {b: {start: drive0, end: drive7}}",
              "beams.b", "drive7");
}

TEST(RobotConfig, UnreadableOrBrokenFiles) {
  EXPECT_THROW(loadRobotConfigFile("data/does_not_exist.yaml"), ConfigError);
  try {
    loadRobotConfigFile("data/broken.yaml");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_THAT(e.problem(), testing::HasSubstr("not valid YAML"));
  }
}

TEST(RobotConfig, SetDriveKeyByFieldName) {
  RobotConfig c = parse(std::string("motor_drives: {drive0: ") + kDrive + "}");
  EXPECT_TRUE(thorvald_base::setDriveKey(c.drives[0], "r_wheel", 0.12));
  EXPECT_DOUBLE_EQ(c.drives[0].r_wheel, 0.12);
  EXPECT_TRUE(thorvald_base::setDriveKey(c.drives[0], "str_llm", 2.0));
  EXPECT_DOUBLE_EQ(c.drives[0].str_lim, 2.0);
  EXPECT_FALSE(thorvald_base::setDriveKey(c.drives[0], "node", 3));
  EXPECT_FALSE(thorvald_base::setDriveKey(c.drives[0], "r_wheel", std::nan("")));
}

namespace {

std::string driveAt(const std::string& name, int node, double x, double y) {
  return name + ": {node: " + std::to_string(node) + ", x: " + std::to_string(x) + ", y: " + std::to_string(y) +
         ", r_wheel: 0.2, prp_gr_rt: 42, prp_enc_ppr: 1024, prp_max_rpm: 3000, str_gr_rt: 42.86, str_enc_ppr: 1024, "
         "str_lim: 3.07}";
}

std::string fourDrives(double x3 = -0.5, double y3 = 0.3, int node3 = 4) {
  return "motor_drives: {" + driveAt("drive0", 1, -0.5, -0.3) + ", " + driveAt("drive1", 2, 0.5, -0.3) + ", " +
         driveAt("drive2", 3, 0.5, 0.3) + ", " + driveAt("drive3", node3, x3, y3) + "}";
}

}  // namespace

TEST(RobotConfig, ImplausibleValuesAreRefusedWithTheirRange) {
  expectError(withDrive0("r_wheel: 0.2", "r_wheel: 1e-9"), "motor_drives.drive0.r_wheel", "[0.02, 1] m");
  expectError(withDrive0("prp_max_rpm: 3000", "prp_max_rpm: 1e-6"), "motor_drives.drive0.prp_max_rpm", "rpm");
  expectError(withDrive0("x: 0.5", "x: 1e300"), "motor_drives.drive0.x", "[-10, 10] m");
  expectError(fourDrives(-1e6), "motor_drives.drive3.x", "physical range");
  expectError(withDrive0("node: 1", "node: 200"), "motor_drives.drive0.node", "CAN node id");
  expectError(std::string("motor_drives: {drive0: ") + kDrive + "}\ncasters: {c0: {x: 0.1, y: 0.2, r_wheel: 50}}",
              "casters.c0.r_wheel", "physical range");
  expectError(std::string("motor_drives: {drive0: ") + kDrive + "}\nbatteries: {bat0: {id: 1, z: -100}}",
              "batteries.bat0.z", "physical range");
  // Drives in the thousands are refused before any of them is read.
  std::string many = "motor_drives: {";
  for (int i = 0; i < 10000; ++i) many += driveAt("drive" + std::to_string(i), 1 + i % 127, 0.0, 0.0) + ", ";
  expectError(many + "}", "motor_drives", "10000 drives, more than 64");
}

TEST(RobotConfig, RunTimeChangesAreHeldToTheSameRanges) {
  RobotConfig c = parse(std::string("motor_drives: {drive0: ") + kDrive + "}");
  ASSERT_TRUE(thorvald_base::setDriveKey(c.drives[0], "r_wheel", 1e9));
  EXPECT_THROW(thorvald_base::validateDrive(c.drives[0], "set_drive_params", "drive0"), ConfigError);
  ASSERT_TRUE(thorvald_base::setDriveKey(c.drives[0], "r_wheel", 0.3));
  EXPECT_NO_THROW(thorvald_base::validateDrive(c.drives[0], "set_drive_params", "drive0"));
  ASSERT_TRUE(thorvald_base::setDriveKey(c.drives[0], "x", -1e6));
  EXPECT_THROW(thorvald_base::validateDrive(c.drives[0], "set_drive_params", "drive0"), ConfigError);
}

TEST(RobotConfig, DegenerateGeometryIsRefused) {
  EXPECT_NO_THROW(parse(fourDrives()));
  expectError(fourDrives(0.5, 0.3), "motor_drives.drive3", "only 0 m from drive2");
  expectError("motor_drives: {" + driveAt("drive0", 1, 0.2, 0.2) + ", " + driveAt("drive1", 2, 0.2, 0.2) + "}",
              "motor_drives.drive1", "overlap");
}

TEST(RobotConfig, DuplicateCanNodeIdsAreRefused) {
  expectError(fourDrives(-0.5, 0.3, 2), "motor_drives.drive3.node", "CAN node id 2 is already used by drive1");
  // Two consecutive fixed drives may be the two channels of one controller; a third on it may not.
  auto fixedAt = [&](const std::string& name, int node, double y) {
    std::string d = driveAt(name, node, 0.0, y);
    return d.substr(0, d.size() - 1) + ", type: 1}";
  };
  EXPECT_NO_THROW(parse("motor_drives: {" + fixedAt("drive0", 1, -0.35) + ", " + fixedAt("drive1", 1, 0.35) + "}"));
  expectError("motor_drives: {" + fixedAt("drive0", 1, -0.7) + ", " + fixedAt("drive1", 1, 0.0) + ", " +
                  fixedAt("drive2", 1, 0.7) + "}",
              "motor_drives.drive2.node", "already used by drive0");
  // A steered CiA 402 drive also occupies node + 64.
  std::string cia = driveAt("drive0", 3, 0.5, 0.0);
  cia = cia.substr(0, cia.size() - 1) + ", protocol: cia402}";
  expectError("motor_drives: {" + cia + ", " + driveAt("drive1", 67, -0.5, 0.0) + "}", "motor_drives.drive1.node",
              "already used by drive0");
}

TEST(RobotConfig, MessagesSayWhatWasFound) {
  expectError("", "<top level>", "is empty");
  expectError("# only a comment\n", "<top level>", "is empty");
  expectError("- drive0\n- drive1\n", "<top level>", "is a list");
  expectError("motor_drives: {}", "motor_drives", "is empty");
  expectError("motor_drives: [1, 2]", "motor_drives", "is a list");
  expectError(std::string("base_driver:\n  ros__parameters:\n    motor_drives: {drive0: ") + kDrive + "}\n",
              "<top level>", "ROS 2 parameters file");
  expectError(std::string("base_driver:\n  ros__parameters:\n    motor_drives: {drive0: ") + kDrive + "}\n",
              "<top level>", "'base_driver/ros__parameters'");
  // A drive written twice in one file (copy and paste) is named as such, not as a missing drive.
  expectError(std::string("motor_drives:\n  drive0: ") + kDrive + "\n  drive0: " + kDrive + "\n", "motor_drives.drive0",
              "given twice");
  expectError(std::string("motor_drives: {drive0: ") + kDrive + ", drive2: " + kDrive + "}", "motor_drives",
              "found drive0, drive2");
}

TEST(RobotConfig, UnknownKeysAreWarnedAtEveryLevel) {
  const RobotConfig c = parse(std::string("motor_drives: {drive0: ") + kDrive + "}\ncaster: {c0: {x: -0.5, y: 0.0}}\n" +
                              "casters: {c1: {x: -0.5, y: 0.1, radius: 0.1}}\n");
  EXPECT_THAT(c.warnings, testing::Contains(testing::HasSubstr("caster: unknown top-level key, ignored (did you "
                                                               "mean 'casters'?)")));
  EXPECT_THAT(c.warnings, testing::Contains(testing::HasSubstr("casters.c1.radius: unknown key")));
  EXPECT_TRUE(c.casters.size() == 1u);
}

TEST(RobotConfig, NearestGroupNames) {
  EXPECT_EQ(thorvald_base::nearestRobotFileGroup("caster"), "casters");
  EXPECT_EQ(thorvald_base::nearestRobotFileGroup("motor_drive"), "motor_drives");
  EXPECT_EQ(thorvald_base::nearestRobotFileGroup("passive_wheel"), "passive_wheels");
  EXPECT_EQ(thorvald_base::nearestRobotFileGroup("pipes"), "pipes");
  EXPECT_EQ(thorvald_base::nearestRobotFileGroup("robot_description"), "");
  EXPECT_EQ(thorvald_base::nearestRobotFileGroup("tf_prefix"), "");
  EXPECT_EQ(thorvald_base::nearestRobotFileGroup("base_driver"), "");
  EXPECT_EQ(thorvald_base::nearestRobotFileGroup("id"), "");
}

TEST(RobotConfig, ImplementCanIds) {
  const std::string drives = std::string("motor_drives: {drive0: ") + kDrive + "}\n";
  EXPECT_TRUE(parse(drives).implement_can_ids.empty());
  // Hexadecimal as users write CAN ids, decimal, and numbers written as strings.
  const RobotConfig c = parse(drives + "implement_can_ids: [0x181, 1284, \"0x7FF\", 1]\n");
  EXPECT_EQ(c.implement_can_ids, (std::vector<int>{0x181, 1284, 0x7FF, 1}));
  EXPECT_TRUE(c.warnings.empty());
  expectError(drives + "implement_can_ids: [0x123, 0x800]", "implement_can_ids[1]", "outside 0x001..0x7FF");
  expectError(drives + "implement_can_ids: [0]", "implement_can_ids[0]", "outside 0x001..0x7FF");
  expectError(drives + "implement_can_ids: [-5]", "implement_can_ids[0]", "outside 0x001..0x7FF");
  expectError(drives + "implement_can_ids: [0x123, 291]", "implement_can_ids[1]", "listed twice");
  expectError(drives + "implement_can_ids: [0x12.5]", "implement_can_ids.0", "expected");
  expectError(drives + "implement_can_ids: 0x123", "implement_can_ids", "expected a list");
  expectError(drives + "implement_can_ids: {a: 1}", "implement_can_ids", "expected a list");
  EXPECT_EQ(thorvald_base::nearestRobotFileGroup("implement_can_id"), "implement_can_ids");
}
