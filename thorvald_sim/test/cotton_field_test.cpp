// The cotton field: rows 91.44 cm apart, plants numbered through the field, the rows' end waypoints.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cstdio>

#include "thorvald_sim/mjcf_compiler.h"
#include "thorvald_sim/scene.h"
#include "thorvald_sim/world.h"

namespace ts = thorvald_sim;

namespace {

ts::ModelPtr compile(const ts::WorldDescription& w) {
  return ts::compileXml(ts::composeScene(w, {}, ts::SceneOptions()), w.name);
}

}  // namespace

TEST(CottonField, RowsApartWithTheirEnds) {
  ts::CottonFieldParams p;
  p.rows = 3;
  p.row_length_m = 3.0;  // 11 plants 0.3 m apart
  p.row.first_plant_x_m = 2.0;
  p.row.slope_deg = 2.77;
  ts::CottonFieldTruth t;
  auto model = compile(ts::makeCottonFieldWorld(p, &t));
  ASSERT_EQ(t.row_start.size(), 3u);
  ASSERT_EQ(t.plants.plant_bases.size(), 33u);
  ASSERT_EQ(t.plants.bolls.size(), 99u);
  for (int k = 0; k < 3; ++k) {
    EXPECT_NEAR(t.row_start[k].y(), 0.9144 * k, 1e-12);
    EXPECT_NEAR(t.row_start[k].x(), 2.0, 1e-12);
    EXPECT_NEAR(t.row_end[k].x(), 5.0, 1e-9);
    EXPECT_NEAR(t.row_end[k].y(), 0.9144 * k, 1e-12);
  }
  // Each boll's geom is where the truth says, under its field-wide plant number; one ground.
  for (size_t i = 0; i < t.plants.bolls.size(); ++i) {
    const std::string name = "plant" + std::to_string(t.plants.boll_plant[i]) + "_boll" + std::to_string(i % 3);
    const int g = mj_name2id(model.get(), mjOBJ_GEOM, name.c_str());
    ASSERT_GE(g, 0) << name;
    const Eigen::Vector3d c(model->geom_pos[3 * g], model->geom_pos[3 * g + 1], model->geom_pos[3 * g + 2]);
    EXPECT_NEAR((c - t.plants.bolls[i]).norm(), 0.0, 1e-6) << name;
    EXPECT_EQ(t.plant_row[t.plants.boll_plant[i]], static_cast<int>(i / 33));
    // Ideal plants do not collide unless asked (the wheels run on the neighbouring rows' lines).
    EXPECT_EQ(model->geom_contype[g], 0);
    EXPECT_EQ(model->geom_conaffinity[g], 0);
  }
  EXPECT_GE(mj_name2id(model.get(), mjOBJ_GEOM, "ground"), 0);
  // Rows differ (each its own seed).
  EXPECT_GT((t.plants.bolls[0] - t.plants.bolls[33] - Eigen::Vector3d(0, 0.9144, 0)).norm(), 1e-3);
}

TEST(CottonField, DatasheetRowsCompileWithUniqueNames) {
  ts::CottonFieldParams p;
  p.rows = 2;
  p.row_length_m = 0.6;
  p.row.datasheet = true;
  p.row.realism.clods = 5;
  p.row.realism.weeds = 2;
  ts::CottonFieldTruth t;
  auto model = compile(ts::makeCottonFieldWorld(p, &t));  // duplicate names would not compile
  EXPECT_EQ(t.plants.plant_bases.size(), 6u);
  EXPECT_GE(mj_name2id(model.get(), mjOBJ_GEOM, "row1_clod0"), 0);
}

TEST(CottonField, WaypointFileHoldsTheRowsEnds) {
  ts::CottonFieldParams p;
  p.rows = 2;
  p.row_length_m = 1.5;
  ts::CottonFieldTruth t;
  ts::makeCottonFieldWorld(p, &t);
  const std::string path = "/tmp/thorvald_sim_cotton_field_waypoints_test.yaml";
  ASSERT_TRUE(ts::writeCottonFieldWaypoints(t, path));
  const YAML::Node y = YAML::LoadFile(path);
  ASSERT_EQ(y["rows"].size(), 2u);
  EXPECT_EQ(y["rows"][1]["row"].as<int>(), 1);
  EXPECT_NEAR(y["rows"][1]["start"][1].as<double>(), 0.9144, 1e-9);
  EXPECT_NEAR(y["rows"][1]["end"][0].as<double>(), t.row_end[1].x(), 1e-9);
  std::remove(path.c_str());
  EXPECT_FALSE(ts::writeCottonFieldWaypoints(t, "/nonexistent/dir/w.yaml"));
}

TEST(CottonField, BadParametersAreNamed) {
  ts::CottonFieldParams p;
  p.rows = 0;
  EXPECT_THROW(ts::makeCottonFieldWorld(p, nullptr), std::invalid_argument);
  p.rows = 2;
  p.row_spacing_m = 0.0;
  EXPECT_THROW(ts::makeCottonFieldWorld(p, nullptr), std::invalid_argument);
}
