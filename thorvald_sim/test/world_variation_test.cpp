// Each greenhouse variation shows in the generated world and in its ground truth; off, the world is the ideal one.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <unistd.h>

#include "test_scene.h"
#include "thorvald_sim/greenhouse_world.h"
#include "thorvald_sim/sensor_config.h"
#include "thorvald_sim/sensors.h"

namespace ts = thorvald_sim;

namespace {

/// A capsule's two centre-line ends [m] (from its pose and half length).
std::pair<Eigen::Vector3d, Eigen::Vector3d> capsuleEnds(const ts::test::StaticWorld& w, const std::string& name) {
  const int g = mj_name2id(w.model.get(), mjOBJ_GEOM, name.c_str());
  EXPECT_GE(g, 0) << name;
  if (g < 0) return {Eigen::Vector3d::Constant(NAN), Eigen::Vector3d::Constant(NAN)};
  const Eigen::Vector3d c(w.data->geom_xpos + 3 * g);
  const Eigen::Vector3d axis(w.data->geom_xmat[9 * g + 2], w.data->geom_xmat[9 * g + 5], w.data->geom_xmat[9 * g + 8]);
  const double h = w.model->geom_size[3 * g + 1];
  const Eigen::Vector3d a = c - h * axis, b = c + h * axis;
  return a.x() < b.x() ? std::make_pair(a, b) : std::make_pair(b, a);
}

/// Height of the first surface straight below (x, y) from z = 5 m.
double surfaceBelow(const ts::test::StaticWorld& w, double x, double y, std::string* geom = nullptr) {
  const mjtNum p[3] = {x, y, 5.0}, v[3] = {0, 0, -1};
  int id = -1;
  const double d = mj_ray(w.model.get(), w.data.get(), p, v, nullptr, 1, -1, &id);
  if (geom)
    *geom = id >= 0 && mj_id2name(w.model.get(), mjOBJ_GEOM, id) ? mj_id2name(w.model.get(), mjOBJ_GEOM, id) : "";
  return 5.0 - d;
}

ts::GreenhouseParams params(const ts::GreenhouseVariation& v) {
  ts::GreenhouseParams p;
  p.rail_sets = 4;
  p.variation = v;
  return p;
}

}  // namespace

TEST(GreenhouseVariation, OffIsTheIdealGreenhouseWhateverTheSeed) {
  ts::GreenhouseParams a, b;
  b.variation.seed = 77;
  b.variation.pipe_bend_length_m = 1.0;  // magnitudes zero: nothing is drawn
  EXPECT_FALSE(b.variation.active());
  const std::string wa = ts::makeGreenhouseWorld(a, nullptr).worldbody;
  EXPECT_EQ(wa, ts::makeGreenhouseWorld(b, nullptr).worldbody);
  EXPECT_EQ(wa.find("rusty"), std::string::npos);
  EXPECT_EQ(wa.find("headland_bump"), std::string::npos);
  EXPECT_EQ(wa.find("crate"), std::string::npos);
  const ts::GreenhouseVariation none = ts::greenhouseVariationProfile("none");
  EXPECT_FALSE(none.active());
  EXPECT_TRUE(ts::greenhouseVariationProfile("harsh").active());
  // "pipes": the pipe variations of "harsh" alone, the headland and the sets as drawn.
  const ts::GreenhouseVariation pipes = ts::greenhouseVariationProfile("pipes"),
                                harsh = ts::greenhouseVariationProfile("harsh");
  EXPECT_TRUE(pipes.active());
  EXPECT_EQ(pipes.pipe_end_offset_m, harsh.pipe_end_offset_m);
  EXPECT_EQ(pipes.pipe_gap_probability, harsh.pipe_gap_probability);
  EXPECT_EQ(pipes.rust_probability, harsh.rust_probability);
  EXPECT_EQ(pipes.headland_slope_deg, 0.0);
  EXPECT_EQ(pipes.headland_bumps + pipes.hoses + pipes.crates + pipes.trolleys, 0);
  EXPECT_EQ(pipes.rail_length_jitter_m, 0.0);
  EXPECT_EQ(pipes.set_spacing_jitter_m, 0.0);
  EXPECT_THROW(ts::greenhouseVariationProfile("mild"), std::invalid_argument);
}

TEST(GreenhouseVariation, BentEndsMoveEachPipeStartByItsOffset) {
  ts::GreenhouseVariation v;
  v.pipe_end_offset_m = 0.02;
  v.pipe_bend_length_m = 0.5;
  ts::GreenhouseTruth t;
  ts::test::StaticWorld w(ts::makeGreenhouseWorld(params(v), &t));
  double largest = 0.0;
  for (const auto& s : t.rail_sets)
    for (int side = 0; side < 2; ++side) {
      const std::string name = "rail" + std::to_string(s.index) + (side == 0 ? "_right" : "_left");
      const double dy = s.pipe_start_offset_m[side];
      EXPECT_LE(std::abs(dy), 0.02);
      largest = std::max(largest, std::abs(dy));
      const auto bend = capsuleEnds(w, name + "_s0");
      EXPECT_NEAR(bend.first.y(), s.pipe_y[side] + dy, 1e-7)
          << name;  // MJCF holds 9 digits  // the start sits off the line by dy
      EXPECT_NEAR(bend.first.x(), s.start_x + 0.0255, 1e-9);
      EXPECT_NEAR(bend.second.y(), s.pipe_y[side], 1e-9);  // and the pipe is back on its line after the bend
      EXPECT_NEAR(bend.second.x(), s.start_x + 0.5, 1e-9);
      EXPECT_NEAR(capsuleEnds(w, name + "_s1").first.y(), s.pipe_y[side], 1e-9);
    }
  EXPECT_GT(largest, 0.01);  // eight draws in +-2 cm: at least one beyond 1 cm
}

TEST(GreenhouseVariation, OpenJointsLeaveTheGapBetweenPipePieces) {
  ts::GreenhouseVariation v;
  v.pipe_gap_probability = 1.0;
  v.pipe_gap_m = 0.015;
  ts::GreenhouseTruth t;
  ts::test::StaticWorld w(ts::makeGreenhouseWorld(params(v), &t));
  const double r = 0.0255;
  const auto a = capsuleEnds(w, "rail1_left_s2"), b = capsuleEnds(w, "rail1_left_s3");
  EXPECT_NEAR((b.first.x() - r) - (a.second.x() + r), 0.015, 1e-9);  // surface to surface
  // Without gaps the pieces touch (their caps overlap).
  ts::test::StaticWorld ideal(ts::makeGreenhouseWorld(params({}), nullptr));
  const auto c = capsuleEnds(ideal, "rail1_left_s2"), d = capsuleEnds(ideal, "rail1_left_s3");
  EXPECT_LT((d.first.x() - r) - (c.second.x() + r), 0.0);
}

TEST(GreenhouseVariation, RustyPiecesAreDarkAndNotNamedAsShinyRails) {
  ts::GreenhouseVariation v;
  v.rust_probability = 0.3;
  ts::test::StaticWorld w(ts::makeGreenhouseWorld(params(v), nullptr));
  int rusty = 0, bright = 0;
  for (int g = 0; g < w.model->ngeom; ++g) {
    const char* n = mj_id2name(w.model.get(), mjOBJ_GEOM, g);
    if (!n || w.model->geom_type[g] != mjGEOM_CAPSULE) continue;
    const std::string name(n);
    if (name.rfind("rusty_rail", 0) == 0) {
      ++rusty;
      EXPECT_LT(w.model->geom_rgba[4 * g], 0.5f);  // darker than the steel (0.8)
    } else if (name.rfind("rail", 0) == 0) {
      ++bright;
      EXPECT_GT(w.model->geom_rgba[4 * g], 0.7f);
    }
  }
  EXPECT_GT(rusty, 0);
  EXPECT_GT(bright, rusty);  // about 30 % rusty
}

TEST(GreenhouseVariation, SlopeTiltsTheHeadlandFloorByItsAngle) {
  ts::GreenhouseVariation v;
  v.headland_slope_deg = 2.0;
  ts::GreenhouseTruth t;
  ts::test::StaticWorld w(ts::makeGreenhouseWorld(params(v), &t));
  const int g = mj_name2id(w.model.get(), mjOBJ_GEOM, "headland_floor_s0");
  ASSERT_GE(g, 0);
  const double normal_z = w.data->geom_xmat[9 * g + 8];  // the floor's normal: the box's z axis
  EXPECT_NEAR(std::acos(normal_z), 2.0 * M_PI / 180.0, 1e-9);
  EXPECT_NEAR(surfaceBelow(w, -3.0, 1.0), 3.0 * std::tan(2.0 * M_PI / 180.0), 1e-6);
  EXPECT_NEAR(surfaceBelow(w, -0.01, 1.0), 0.01 * std::tan(2.0 * M_PI / 180.0), 1e-6);  // level with the edge
  EXPECT_NEAR(t.floorHeightAt(-3.0, 1.0), 3.0 * std::tan(2.0 * M_PI / 180.0), 1e-12);
  ts::test::StaticWorld flat(ts::makeGreenhouseWorld(params({}), nullptr));
  EXPECT_NEAR(surfaceBelow(flat, -3.0, 1.0), 0.0, 1e-9);
}

TEST(GreenhouseVariation, BumpsCratesHosesAndTrolleysStandWhereTheTruthSays) {
  ts::GreenhouseVariation v;
  v.headland_bumps = 3;
  v.bump_slope_deg = 2.0;
  v.crates = 2;
  v.hoses = 1;
  v.trolleys = 2;
  ts::GreenhouseTruth t;
  ts::test::StaticWorld w(ts::makeGreenhouseWorld(params(v), &t));
  ASSERT_EQ(t.bumps.size(), 3u);
  const double h = 0.5 / std::sin(2.0 * M_PI / 180.0) * (1.0 - std::cos(2.0 * M_PI / 180.0));  // cap height
  for (const auto& b : t.bumps) {
    EXPECT_NEAR(surfaceBelow(w, b.x(), b.y()), h, 1e-6);
    EXPECT_NEAR(b.z(), h, 1e-9);
  }
  ASSERT_EQ(t.obstacles.size(), 5u);
  for (const auto& o : t.obstacles) {
    std::string hit;
    const double z = surfaceBelow(w, o.x, o.y, &hit);
    EXPECT_EQ(hit, o.name);
    EXPECT_NEAR(z, o.height, 1e-6) << o.name;
    if (o.kind == "trolley") EXPECT_NEAR(o.x, v.trolley_x_m, 1e-12);
    if (o.kind == "crate") EXPECT_LT(o.x, t.rear_wall_x + 1.0);
  }
  EXPECT_NE(t.obstacles[3].y, t.obstacles[4].y);  // two trolleys, two rows
}

TEST(GreenhouseVariation, RailSetsOfOtherLengthsAndSpacings) {
  ts::GreenhouseVariation v;
  v.rail_length_jitter_m = 3.0;
  v.set_spacing_jitter_m = 0.1;
  ts::GreenhouseTruth t;
  ts::test::StaticWorld w(ts::makeGreenhouseWorld(params(v), &t));
  double lmin = 1e9, lmax = 0, moved = 0;
  for (const auto& s : t.rail_sets) {
    EXPECT_LE(s.length_m, 20.0);
    EXPECT_GE(s.length_m, 17.0);
    lmin = std::min(lmin, s.length_m), lmax = std::max(lmax, s.length_m);
    EXPECT_LE(std::abs(s.start_y - 1.6 * s.index), 0.1 + 1e-12);
    moved = std::max(moved, std::abs(s.start_y - 1.6 * s.index));
    const int pieces = static_cast<int>(std::ceil((s.length_m - 2 * 0.0255) / 2.0));
    const auto last = capsuleEnds(w, "rail" + std::to_string(s.index) + "_right_s" + std::to_string(pieces - 1));
    EXPECT_NEAR(last.second.x(), s.start_x + s.length_m - 0.0255, 1e-7);  // the pipe ends where the truth says
  }
  EXPECT_GT(lmax - lmin, 0.3);
  EXPECT_GT(moved, 0.02);
  for (size_t k = 1; k + 1 < t.plant_row_y.size(); ++k)  // plant rows stay midway between their sets
    EXPECT_NEAR(t.plant_row_y[k], 0.5 * (t.rail_sets[k - 1].start_y + t.rail_sets[k].start_y), 1e-9);
}

// The plants of each row run from plant_row_start past the rails' start to plant_row_end_gap before the end of the
// shorter set beside them (the robot's lamps stand on the rails beside the last plant); the truth says so per set.
TEST(GreenhouseVariation, PlantRowsEndBeforeTheShorterSetBesideThem) {
  ts::GreenhouseVariation v;
  v.rail_length_jitter_m = 3.0;
  ts::GreenhouseParams p = params(v);
  ts::GreenhouseTruth t;
  ts::test::StaticWorld w(ts::makeGreenhouseWorld(p, &t));
  const int n = static_cast<int>(t.rail_sets.size());
  int rows_checked = 0;
  for (int k = 0; k <= n; ++k) {
    const std::string name = "plant_row" + std::to_string(k);
    double lo = 1e9, hi = -1e9;
    for (int i = 0;; ++i) {
      const int g = mj_name2id(w.model.get(), mjOBJ_GEOM, (name + "_s" + std::to_string(i)).c_str());
      if (g < 0) break;
      lo = std::min(lo, w.data->geom_xpos[3 * g] - w.model->geom_size[3 * g]);
      hi = std::max(hi, w.data->geom_xpos[3 * g] + w.model->geom_size[3 * g]);
    }
    if (hi < lo) continue;  // an outer row outside the side walls
    const int left = std::max(0, k - 1), right = std::min(n - 1, k);
    const double shorter = std::min(t.rail_sets[left].length_m, t.rail_sets[right].length_m);
    EXPECT_NEAR(lo, p.rail_start_gap_m + p.plant_row_start_m, 1e-7) << name;
    EXPECT_NEAR(hi, p.rail_start_gap_m + shorter - p.plant_row_end_gap_m, 1e-7) << name;
    ++rows_checked;
  }
  EXPECT_GE(rows_checked, n);
  for (int k = 0; k < n; ++k) {  // the set's plants end where the longer of its two rows ends
    const auto& s = t.rail_sets[k];
    const double own = s.length_m, l = k > 0 ? std::min(own, t.rail_sets[k - 1].length_m) : own,
                 r = k + 1 < n ? std::min(own, t.rail_sets[k + 1].length_m) : own;
    EXPECT_DOUBLE_EQ(s.plants_from_m, p.plant_row_start_m);
    EXPECT_NEAR(s.plants_to_m, std::max(l, r) - p.plant_row_end_gap_m, 1e-12) << k;
    EXPECT_LE(s.plants_to_m, s.length_m - p.plant_row_end_gap_m + 1e-12);  // never past the lamps' reach
  }
  const std::string path = "/tmp/thorvald_sim_plants_truth_" + std::to_string(::getpid()) + ".yaml";
  ASSERT_TRUE(ts::writeGreenhouseTruth(t, path));
  const YAML::Node y = YAML::LoadFile(path);
  std::remove(path.c_str());
  ASSERT_EQ(y["rail_sets"][1]["plants"].size(), 2u);
  EXPECT_NEAR(y["rail_sets"][1]["plants"][1].as<double>(), t.rail_sets[1].plants_to_m, 1e-4);
  // Rails too short for a row: no plants, an empty list in the truth.
  p.rail_length_m = 1.5;
  p.variation = ts::GreenhouseVariation();
  ts::makeGreenhouseWorld(p, &t);
  EXPECT_TRUE(t.plant_row_y.empty());
  ASSERT_TRUE(ts::writeGreenhouseTruth(t, path));
  EXPECT_EQ(YAML::LoadFile(path)["rail_sets"][0]["plants"].size(), 0u);
  std::remove(path.c_str());
}

TEST(GreenhouseVariation, SameSeedSameHouseOtherSeedOtherHouse) {
  ts::GreenhouseVariation v = ts::greenhouseVariationProfile("harsh");
  const std::string a = ts::makeGreenhouseWorld(params(v), nullptr).worldbody;
  EXPECT_EQ(a, ts::makeGreenhouseWorld(params(v), nullptr).worldbody);
  v.seed = 2;
  EXPECT_NE(a, ts::makeGreenhouseWorld(params(v), nullptr).worldbody);
  ts::test::StaticWorld w(ts::makeGreenhouseWorld(params(v), nullptr));  // compiles
  EXPECT_GT(w.model->ngeom, 100);
}

TEST(GreenhouseVariation, TruthFileDescribesTheActualRails) {
  ts::GreenhouseTruth t;
  ts::makeGreenhouseWorld(params(ts::greenhouseVariationProfile("harsh")), &t);
  const std::string path = "/tmp/thorvald_sim_variation_test_truth.yaml";
  ASSERT_TRUE(ts::writeGreenhouseTruth(t, path));
  const YAML::Node y = YAML::LoadFile(path);
  ASSERT_EQ(y["rail_sets"].size(), 4u);
  for (size_t k = 0; k < 4; ++k) {
    EXPECT_NEAR(y["rail_sets"][k]["length"].as<double>(), t.rail_sets[k].length_m, 1e-5);
    EXPECT_NEAR(y["rail_sets"][k]["y"].as<double>(), t.rail_sets[k].start_y, 1e-5);
    EXPECT_NEAR(y["rail_sets"][k]["pipe_start_offset"][1].as<double>(), t.rail_sets[k].pipe_start_offset_m[1], 1e-6);
  }
  EXPECT_EQ(y["obstacles"].size(), t.obstacles.size());
  EXPECT_NEAR(y["headland_slope"].as<double>(), M_PI / 180.0, 1e-6);
  std::remove(path.c_str());
}

TEST(GreenhouseVariation, BadValuesAreNamed) {
  auto refused = [](ts::GreenhouseVariation v, const std::string& key) {
    try {
      ts::makeGreenhouseWorld(params(v), nullptr);
      ADD_FAILURE() << "accepted a bad " << key;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("variation/" + key), std::string::npos) << e.what();
    }
  };
  ts::GreenhouseVariation v;
  v.pipe_end_offset_m = 0.5;
  refused(v, "pipe_end_offset");
  v = {};
  v.rust_probability = 1.5;
  refused(v, "rust_probability");
  v = {};
  v.set_spacing_jitter_m = 0.6;  // sets would overlap
  refused(v, "set_spacing_jitter");
  v = {};
  v.rail_length_jitter_m = 19.5;
  refused(v, "rail_length_jitter");
}

TEST(GreenhouseVariation, RobotDrivesOnTheHarshHeadland) {
  ts::GreenhouseParams p = params(ts::greenhouseVariationProfile("harsh"));
  p.variation.headland_slope_deg = 2.0;  // the steepest the issue asks for, bumps on top
  ts::GreenhouseTruth t;
  const ts::WorldDescription w = ts::makeGreenhouseWorld(p, &t);
  ts::RobotSpawn s;
  s.mjcf = ts::urdfToMjcf(ts::referenceUrdf(ts::test::fourWheelSteered(), ""), &s.root_link);
  s.x = -3.0, s.y = 0.5, s.yaw = M_PI / 2;  // along the headland, across the slope
  s.z = t.floorHeightAt(s.x, s.y) + 0.01;   // as the node lifts a robot onto the slope
  ts::Simulation sim(ts::composeScene(w, {s}, ts::SceneOptions()), {s});
  ts::DrivenRobot robot(sim, ts::test::fourWheelSteered(), "");
  const Eigen::Vector3d start = sim.robotState(0).position;
  for (double t_s = 0.0; t_s < 6.0; t_s += 0.02) {
    robot.command({0.5, 0.0, 0.0}, t_s);
    robot.control(t_s);
    sim.step(10);
  }
  const Eigen::Vector3d end = sim.robotState(0).position;
  EXPECT_EQ(sim.divergences(), 0u);
  EXPECT_GT(end.y() - start.y(), 2.0);    // 3 m commanded
  EXPECT_NEAR(end.z(), start.z(), 0.15);  // still on the floor, not fallen through
}

// The greenhouse robot's down-facing range finders (sensors_greenhouse_datasheet.yaml) swept along a pipe across an
// open joint. On the rails base_link stays at the headland floor's height (rail wheels 0.12 m on pipe tops 0.055 m
// up, floor wheels 0.175 m), so a sensor reads its mount height less the pipe top there.
namespace {

/// Readings every 5 mm from 0.15 m before to 0.15 m after x_centre, the sensor `beside` m outward of the
/// right pipe's centre line of set 1.
std::vector<double> sweepAlongPipe(const ts::test::StaticWorld& w, const ts::GreenhouseTruth& t, double x_centre,
                                   double beside, const ts::SensorConfig& c) {
  const ts::RailSetTruth& s = t.rail_sets[1];
  ts::UltrasonicSpec spec = c.ultrasonic;
  spec.noise_m = 0.0;
  ts::RayCaster caster(w.model.get(), w.data.get(), -1);
  std::mt19937 rng(1);
  ts::SensorPose pose;
  pose.rotation =
      (Eigen::AngleAxisd(c.rpy.z(), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(c.rpy.y(), Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(c.rpy.x(), Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  std::vector<double> out;
  for (int i = -30; i <= 30; ++i) {
    pose.origin = {x_centre + 0.005 * i, s.pipe_y[0] - beside, t.floor_z + c.xyz.z()};  // right pipe: outward is -y
    out.push_back(ts::simulateUltrasonic(caster, pose, spec, rng));
  }
  return out;
}

std::string listed(const std::vector<double>& r) {
  std::string line;
  for (double v : r) line += std::to_string(v).substr(0, 5) + " ";
  return line;
}

}  // namespace

// Issue 29: an 8-set datasheet run aborted on "edge under mid_right" at an open joint. A sawn pipe's end is flat:
// over a 1 cm gap between two pipe tops the range finders' cones (0.35 rad, 5 cm across the pipe top) still hear
// the pipe; past the pipe's true end they read the rows' ground (an edge), as they must.
TEST(GreenhouseVariation, AnOpenJointIsNoEdgeToTheRangeFinders) {
  ts::GreenhouseVariation v;
  v.pipe_gap_probability = 1.0;  // every joint open
  v.pipe_gap_m = 0.01;           // the pipes and harsh profiles' gap
  ts::GreenhouseTruth t;
  ts::test::StaticWorld w(ts::makeGreenhouseWorld(params(v), &t));
  const auto a = capsuleEnds(w, "rail1_right_s2"), b = capsuleEnds(w, "rail1_right_s3");
  const double joint = 0.5 * (a.second.x() + b.first.x());
  const double rail_top = t.pipe_centre_z + 0.5 * t.params.pipe_diameter_m;
  const double gauge_half = 0.5 * t.params.rail_gauge_m;
  int checked = 0;
  for (const auto& c : ts::loadSensorConfigFile(std::string(SIM_CONFIG_DIR) + "/sensors_greenhouse_datasheet.yaml")) {
    if (c.type != ts::SensorType::kUltrasonic || std::abs(c.rpy.y() - M_PI / 2) > 0.01) continue;  // down-facing
    ++checked;
    const double rail_reading = c.xyz.z() - rail_top;
    // The robot up to 2 cm off the rails' centre line (entries are 0.5-1.6 cm off): the mount 0.30 m from it, the
    // pipe 0.275 m; every 2.5 mm.
    for (int k = -8; k <= 8; ++k) {
      const double off = 0.0025 * k;
      const double beside = std::abs(c.xyz.y()) - gauge_half + off;
      const std::vector<double> r = sweepAlongPipe(w, t, joint, beside, c);
      const long bad = std::count_if(r.begin(), r.end(), [&](double x) { return std::abs(x - rail_reading) > 0.02; });
      EXPECT_EQ(bad, 0) << c.name << " off " << off << ": " << listed(r);
      // The pipe's true end: the sensor reads the rows' ground there (0.15 m below the floor).
      const std::vector<double> end = sweepAlongPipe(w, t, t.rail_sets[1].start_x + t.rail_sets[1].length_m, beside, c);
      EXPECT_GT(end.back(), c.xyz.z() + 0.1) << c.name << " off " << off << ": " << listed(end);
    }
  }
  EXPECT_EQ(checked, 4);
}
