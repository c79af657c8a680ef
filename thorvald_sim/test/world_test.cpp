// The generated worlds hold what their ground truth says.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>

#include "thorvald_sim/mjcf_compiler.h"
#include "thorvald_sim/scene.h"
#include "thorvald_sim/world.h"

namespace ts = thorvald_sim;

namespace {

ts::ModelPtr compile(const ts::WorldDescription& w) {
  return ts::compileXml(ts::composeScene(w, {}, ts::SceneOptions()), w.name);
}

Eigen::Vector3d geomPos(const mjModel* m, const std::string& name) {
  const int g = mj_name2id(m, mjOBJ_GEOM, name.c_str());
  EXPECT_GE(g, 0) << name;
  if (g < 0) return Eigen::Vector3d::Constant(NAN);
  return {m->geom_pos[3 * g], m->geom_pos[3 * g + 1], m->geom_pos[3 * g + 2]};
}

}  // namespace

TEST(Greenhouse, RailsWhereTheTruthSays) {
  ts::GreenhouseParams p;
  p.rail_sets = 4;
  p.set_spacing_m = 1.5;
  p.rail_gauge_m = 0.6;
  ts::GreenhouseTruth t;
  auto model = compile(ts::makeGreenhouseWorld(p, &t));
  ASSERT_EQ(t.rail_sets.size(), 4u);
  for (const auto& s : t.rail_sets) {
    EXPECT_NEAR(s.pipe_y[1] - s.pipe_y[0], 0.6, 1e-12);
    EXPECT_NEAR(s.start_y, 1.5 * s.index, 1e-12);
    const int g = mj_name2id(model.get(), mjOBJ_GEOM, ("rail" + std::to_string(s.index) + "_right_s0").c_str());
    ASSERT_GE(g, 0);
    EXPECT_EQ(model->geom_type[g], mjGEOM_CAPSULE);
    EXPECT_NEAR(model->geom_size[3 * g], 0.0255, 1e-9);  // 51 mm pipe
    // A capsule's centre sits half its length past the start.
    const Eigen::Vector3d c = geomPos(model.get(), "rail" + std::to_string(s.index) + "_right_s0");
    EXPECT_NEAR(c.x() - model->geom_size[3 * g + 1] - model->geom_size[3 * g], s.start_x, 1e-9);
    EXPECT_NEAR(c.y(), s.pipe_y[0], 1e-9);
    EXPECT_NEAR(c.z() + 0.0255, p.rail_top_m, 1e-9);
  }
  EXPECT_EQ(t.edge_x, 0.0);
  EXPECT_EQ(t.plant_row_y.size(), 5u);
  EXPECT_FALSE(t.vent_line_y.empty());
  for (double y : t.vent_line_y) {  // ventilation lines lie midway between neighbouring rail sets
    const double k = y / 1.5 + 0.5;
    EXPECT_NEAR(k, std::round(k), 1e-9);
  }
}

TEST(Greenhouse, TruthFileRoundTrips) {
  ts::GreenhouseTruth t;
  ts::makeGreenhouseWorld(ts::GreenhouseParams(), &t);
  const std::string path = "/tmp/thorvald_sim_world_test_truth.yaml";
  ASSERT_TRUE(ts::writeGreenhouseTruth(t, path));
  const YAML::Node y = YAML::LoadFile(path);
  EXPECT_DOUBLE_EQ(y["rail_gauge"].as<double>(), 0.55);
  EXPECT_DOUBLE_EQ(y["pipe_diameter"].as<double>(), 0.051);
  ASSERT_EQ(y["rail_sets"].size(), t.rail_sets.size());
  EXPECT_NEAR(y["rail_sets"][3]["y"].as<double>(), t.rail_sets[3].start_y, 1e-6);
  EXPECT_NEAR(y["edge"]["x"].as<double>(), 0.0, 1e-12);
  std::remove(path.c_str());
}

TEST(Greenhouse, BadParametersAreNamed) {
  ts::GreenhouseParams p;
  p.rail_gauge_m = 2.0;
  try {
    ts::makeGreenhouseWorld(p, nullptr);
    FAIL() << "accepted a gauge wider than the set spacing";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("rail_gauge"), std::string::npos);
  }
  p = ts::GreenhouseParams();
  p.pipe_diameter_m = -1;
  EXPECT_THROW(ts::makeGreenhouseWorld(p, nullptr), std::invalid_argument);
  p = ts::GreenhouseParams();
  p.plant_bottom_m = p.plant_top_m;
  try {
    ts::makeGreenhouseWorld(p, nullptr);
    FAIL() << "accepted plants hanging from their top";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("plant_bottom"), std::string::npos);
  }
}

TEST(Greenhouse, OuterPlantRowsOnlyInsideTheSideWalls) {
  ts::GreenhouseParams p;
  p.rail_sets = 3;
  ts::GreenhouseTruth t;
  ts::makeGreenhouseWorld(p, &t);  // walls 1.2 m beside the outer sets: a row beside each of them
  ASSERT_EQ(t.plant_row_y.size(), 4u);
  EXPECT_NEAR(t.plant_row_y.front(), -0.8, 1e-9);
  p.wall_margin_m = 0.5 * p.set_spacing_m;  // side walls where the outer rows would hang: only the inner rows
  ts::makeGreenhouseWorld(p, &t);
  ASSERT_EQ(t.plant_row_y.size(), 2u);
  EXPECT_NEAR(t.plant_row_y[0], 0.8, 1e-9);
  EXPECT_NEAR(t.plant_row_y[1], 2.4, 1e-9);
  EXPECT_NEAR(t.side_wall_y[0], -0.8, 1e-9);
}

TEST(CottonRow, PlantsThirtyCentimetresApartOnTheSlope) {
  for (double slope : {0.0, 0.25, 2.77}) {
    ts::CottonRowParams p;
    p.slope_deg = slope;
    ts::CottonRowTruth t;
    auto model = compile(ts::makeCottonRowWorld(p, &t));
    ASSERT_EQ(t.plant_bases.size(), 10u);
    for (size_t i = 1; i < t.plant_bases.size(); ++i)
      EXPECT_NEAR(t.plant_bases[i].x() - t.plant_bases[i - 1].x(), 0.30, 1e-12);
    for (const auto& b : t.plant_bases) EXPECT_NEAR(b.z(), b.x() * std::tan(slope * M_PI / 180), 1e-12);
    // The ground plane is tilted by the slope: its normal leans back by the slope angle.
    const int g = mj_name2id(model.get(), mjOBJ_GEOM, "ground");
    ASSERT_GE(g, 0);
    mjtNum mat[9];
    mju_quat2Mat(mat, model->geom_quat + 4 * g);
    EXPECT_NEAR(std::acos(mat[8]), slope * M_PI / 180, 1e-6);
    EXPECT_LT(mat[2], 1e-12);  // normal tilted towards -x: the ground rises along +x
    ASSERT_EQ(t.bolls.size(), 30u);
    for (size_t i = 0; i < t.bolls.size(); ++i) {
      const Eigen::Vector3d c =
          geomPos(model.get(), "plant" + std::to_string(t.boll_plant[i]) + "_boll" + std::to_string(i % 3));
      EXPECT_NEAR((c - t.bolls[i]).norm(), 0.0, 1e-6);
      const int bg = mj_name2id(model.get(), mjOBJ_GEOM,
                                ("plant" + std::to_string(t.boll_plant[i]) + "_boll" + std::to_string(i % 3)).c_str());
      EXPECT_EQ(model->geom_rgba[4 * bg], 1.0f);  // white
      EXPECT_EQ(model->geom_rgba[4 * bg + 2], 1.0f);
    }
  }
}

TEST(CottonRow, SameSeedSameBolls) {
  ts::CottonRowTruth a, b, c;
  ts::CottonRowParams p;
  ts::makeCottonRowWorld(p, &a);
  ts::makeCottonRowWorld(p, &b);
  p.seed = 2;
  ts::makeCottonRowWorld(p, &c);
  EXPECT_EQ((a.bolls[4] - b.bolls[4]).norm(), 0.0);
  EXPECT_GT((a.bolls[4] - c.bolls[4]).norm(), 1e-3);
}
