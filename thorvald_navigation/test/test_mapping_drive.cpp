// The scripted mapping drive (config/greenhouse_mapping_drive.yaml) driven kinematically from the launch's start pose
// in the tightest greenhouse it is used in: the robot's frame must stay on the headland floor, clear of the side walls,
// the rear wall and the rails' start, at every step. A drive that collides in the simulator leaves the robot pushing
// against a wall while the wheel odometry runs on, and the map is made of scans from a stuck, tilted robot.
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "thorvald_base/pose2d.h"

namespace {

struct Segment {
  double vx_mps, wz_radps, duration_s;
};

std::vector<Segment> loadDrive(const std::string& path) {
  const YAML::Node root = YAML::LoadFile(path);
  std::vector<Segment> out;
  for (const auto& s : root["segments"]) out.push_back({s[0].as<double>(), s[1].as<double>(), s[2].as<double>()});
  return out;
}

// greenhouse_rail_robot's frame (thorvald_bringup's greenhouse_frame.urdf: a 1.05 m x 0.92 m plate centred 0.325 m
// behind base_link, the front axle); the wheels and casters are inside it.
const std::array<Eigen::Vector2d, 4> kFrameCorners = {Eigen::Vector2d(0.2, 0.46), Eigen::Vector2d(0.2, -0.46),
                                                      Eigen::Vector2d(-0.85, 0.46), Eigen::Vector2d(-0.85, -0.46)};

// Headland of a generated greenhouse (world frame: x along the rows from the headland edge, rail set 0 at y = 0).
struct Headland {
  double rear_x = -6.0, edge_x = 0.0, side_y_min = -0.8, side_y_max = 2.4;
};

// Smallest clearance of the frame's corners to the headland's bounds over the whole drive [m] (negative: collision).
double minClearance(const std::vector<Segment>& drive, const thorvald_base::Pose2D& start, const Headland& h) {
  thorvald_base::Pose2D pose = start;
  double worst = 1e9;
  const double dt = 0.01;
  auto check = [&]() {
    for (const auto& c : kFrameCorners) {
      const Eigen::Vector2d p = pose.transformPoint(c);
      worst = std::min({worst, p.x() - h.rear_x, h.edge_x - p.x(), p.y() - h.side_y_min, h.side_y_max - p.y()});
    }
  };
  check();
  for (const auto& s : drive)
    for (double t = 0.0; t < s.duration_s; t += dt) {
      pose = pose * thorvald_base::Pose2D{s.vx_mps * dt, 0.0, s.wz_radps * dt};
      check();
    }
  return worst;
}

const std::string kDrive = std::string(THORVALD_NAVIGATION_SOURCE_DIR) + "/config/greenhouse_mapping_drive.yaml";
const thorvald_base::Pose2D kStart{-2.5, 0.0, 0.0};  // thorvald_bringup's sim.launch start in the greenhouse

}  // namespace

// greenhouse_rail_nav's simulated greenhouse (side walls half a set spacing, 0.8 m, from the outer sets' centres), 2
// rail sets as its mapping launch's default: the narrowest headland the drive is used in.
TEST(MappingDrive, StaysClearOfTheWallsInTheNarrowestHeadland) {
  const std::vector<Segment> drive = loadDrive(kDrive);
  ASSERT_FALSE(drive.empty());
  EXPECT_GT(minClearance(drive, kStart, Headland{}), 0.05);
}

// The check itself: a full turn on the spot where the drive starts sweeps the frame's rear corners 0.97 m around the
// front axle, past the side wall 0.8 m away.
TEST(MappingDrive, AFullTurnAtTheStartWouldHitTheSideWall) {
  const std::vector<Segment> full_turn = {{0.0, 0.4, 2.0 * thorvald_base::kPi / 0.4}};
  EXPECT_LT(minClearance(full_turn, kStart, Headland{}), 0.0);
  Headland wide;  // thorvald_sim's default greenhouse: side walls 1.2 m from the outer sets
  wide.side_y_min = -1.2;
  wide.side_y_max = 4.4;
  EXPECT_GT(minClearance(full_turn, kStart, wide), 0.0);
}
