// TopicHarvestPlant against fake perception and manipulator topics: an observation takes the end effector of its
// own frame only, the arm's calibrated position stands in when perception did not report the housing, the arm goes
// where a rover move asks; and HarvestActions on this plant: the vacuum stays on while the arm retracts from the
// boll, the search under the leaves sweeps the leaf in the arm's strip.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <atomic>
#include <cmath>
#include <functional>
#include <future>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <geometry_msgs/PointStamped.h>
#include <sensor_msgs/PointCloud2.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <std_msgs/Bool.h>
#include <std_msgs/Float64.h>
#include <thorvald_common/ros/wait_for.h>

#include "cotton_harvester/BollArray.h"
#include "../../src/ros/topic_harvest_plant.h"
#include "cotton_harvester/control/harvest_actions.h"
#include "fake_rover_topics.h"

namespace cotton_harvester {
namespace control {
namespace {

using fake::FakeRover;
using fake::FrameStream;

/// Waits for `done` while the AsyncSpinner of main() runs the callbacks.
bool waitUntil(const std::function<bool()>& done, double timeout_s) {
  return thorvald_common::waitFor(done, timeout_s, thorvald_common::sleepEvery(0.005));
}

const HarvestPlant::Preempted kNever = [] { return false; };

std::string uniqueNamespace() {
  static std::atomic<int> n{0};
  return "plant_test_" + std::to_string(++n);
}

TopicPlantParams testParams() {
  TopicPlantParams p;
  p.settle_s = 0.0;
  p.observe_timeout_s = 5.0;
  p.effector_max_age_s = 0.5;
  p.arm_timeout_s = 10.0;
  p.joint_max_age_s = 1.0;  // joint states at 50 Hz of wall time, however loaded the machine
  return p;
}

/// The manoeuvres' settings of these tests: the arm's plane at camera y 0.02, a short dwell.
HarvestActionParams actionParams() {
  HarvestActionParams a;
  a.arm.extension_zero_x_m = -0.55;
  a.arm.strip_y_m = 0.02;
  a.pick_dwell_s = 0.2;
  return a;
}

struct Rig {
  explicit Rig(const TopicPlantParams& params, const HarvestActionParams& actions = actionParams(),
               bool rover_position = true)
      : ns(uniqueNamespace()), fake(ns, rover_position), nh(ns), plant(nh, params, actions.arm) {
    EXPECT_TRUE(waitUntil([this] { return fake.connected(); }, 30.0)) << "topics did not connect";
    // The plant has the arm's joint states before the test starts.
    EXPECT_TRUE(waitUntil([this] { return plant.hasArmState(); }, 30.0)) << "no joint states";
  }
  std::string ns;
  FakeRover fake;
  ros::NodeHandle nh;
  TopicHarvestPlant plant;
};

TEST(TopicHarvestPlant, ObservationTakesItsOwnFramesEndEffector) {
  Rig rig(testParams());
  const ros::Time now = ros::Time::now();
  rig.fake.publishFrame(now, true, -0.20, 1.40);
  ros::WallDuration(0.1).sleep();
  auto first = rig.plant.observe(kNever);
  ASSERT_TRUE(first);
  ASSERT_TRUE(first->end_effector);
  EXPECT_NEAR(first->end_effector->x, -0.20, 1e-9);
  EXPECT_NEAR(first->end_effector->z, 1.40, 1e-9);

  // A newer frame without its own end effector: the older frame's is not taken for it (the arm may have moved).
  rig.fake.publishFrame(now + ros::Duration(0.25), false);
  auto second = rig.plant.observe(kNever);
  ASSERT_TRUE(second);
  EXPECT_EQ(second->bolls.size(), 1u);
  EXPECT_FALSE(second->end_effector);
  EXPECT_EQ(rig.plant.effectorFromCalibration(), 0u);
}

TEST(TopicHarvestPlant, CalibratedPositionStandsInWhenPerceptionMissesTheHousing) {
  TopicPlantParams params = testParams();
  params.effector_from_calibration = true;
  Rig rig(params);
  rig.fake.publishFrame(ros::Time::now(), false);
  auto obs = rig.plant.observe(kNever);
  ASSERT_TRUE(obs);
  ASSERT_TRUE(obs->end_effector);
  // extension 0.35 and depth 1.2 (the fake arm's rest) through the calibration
  EXPECT_NEAR(obs->end_effector->x, 0.35 - 0.55, 1e-9);
  EXPECT_NEAR(obs->end_effector->y, 0.02, 1e-9);
  EXPECT_NEAR(obs->end_effector->z, 1.2, 1e-9);
  EXPECT_EQ(rig.plant.effectorFromCalibration(), 1u);

  // Perception's own position wins when it reports one.
  const ros::Time stamp = ros::Time::now();
  rig.fake.publishFrame(stamp, true, -0.19, 1.22);
  auto seen = rig.plant.observe(kNever);
  ASSERT_TRUE(seen && seen->end_effector);
  EXPECT_NEAR(seen->end_effector->x, -0.19, 1e-9);
  EXPECT_EQ(rig.plant.effectorFromCalibration(), 1u);
}

TEST(TopicHarvestPlant, NoCalibratedPositionFromStaleJointStates) {
  TopicPlantParams params = testParams();
  params.effector_from_calibration = true;
  Rig rig(params);
  // A frame stamped 5 s back: no joint state near it.
  rig.fake.publishFrame(ros::Time::now() - ros::Duration(5.0), false);
  auto obs = rig.plant.observe(kNever);
  ASSERT_TRUE(obs);
  EXPECT_FALSE(obs->end_effector);
  EXPECT_EQ(rig.plant.effectorFromCalibration(), 0u);
}

// The pick is HarvestActions' on the topic plant's primitives (arm target, brush, wait).
TEST(TopicHarvestPlant, VacuumStaysOnWhileTheArmRetracts) {
  Rig rig(testParams());
  const double start = rig.fake.extension();  // the rest extension, 0.35
  HarvestActions actions(rig.plant, actionParams());
  EXPECT_EQ(actions.pick(0.20, kNever), MoveResult::kDone);
  ASSERT_TRUE(waitUntil([&] { return rig.fake.brushEvents().size() >= 2; }, 10.0));
  const auto events = rig.fake.brushEvents();
  ASSERT_EQ(events.size(), 2u);
  EXPECT_TRUE(events[0].first);
  EXPECT_NEAR(events[0].second, start + 0.20, 1e-9);  // on at the boll
  EXPECT_FALSE(events[1].first);
  EXPECT_NEAR(events[1].second, start, 1e-9);  // off only once the arm is back
  EXPECT_NEAR(rig.fake.extension(), start, 1e-9);
}

TEST(TopicHarvestPlant, VacuumOffBeforeRetractingWhenAsked) {
  HarvestActionParams params = actionParams();
  params.vacuum_while_retracting = false;
  Rig rig(testParams(), params);
  const double start = rig.fake.extension();
  HarvestActions actions(rig.plant, params);
  EXPECT_EQ(actions.pick(0.15, kNever), MoveResult::kDone);
  ASSERT_TRUE(waitUntil([&] { return rig.fake.brushEvents().size() >= 2; }, 10.0));
  const auto events = rig.fake.brushEvents();
  ASSERT_EQ(events.size(), 2u);
  EXPECT_FALSE(events[1].first);
  EXPECT_GT(events[1].second, start + 0.10);  // off at the boll, before the arm has come far back
}

TopicPlantParams searchParams() {
  TopicPlantParams p = testParams();
  p.cloud = true;
  p.effector_from_calibration = true;
  return p;
}

// The search is HarvestActions' on the topic plant's primitives (frames, their clouds, arm targets).
TEST(TopicHarvestPlant, LookingUnderTheLeavesSweepsTheLeafInTheArmsStrip) {
  Rig rig(searchParams());
  FrameStream frames(rig.fake, true);
  HarvestActions actions(rig.plant, actionParams());  // rest depth 1.2 m, where the fake arm starts
  const auto result = actions.searchUnderLeaves(kNever);
  ASSERT_TRUE(result) << "the leaf is a layer to sweep";
  EXPECT_EQ(*result, MoveResult::kDone);
  EXPECT_EQ(actions.leafSearches(), 1);
  EXPECT_EQ(actions.leafSweeps(), 1);  // nothing deeper than the leaf but the ground
  // The sweep: to beside the leaf above the plants, down to 1 cm above its top, sideways through it to 15 cm past
  // its far edge (housing half side 5 cm), up to the rest depth.
  const auto t = rig.fake.targets();
  const auto down = std::find_if(t.begin(), t.end(), [](const auto& p) { return std::abs(p.second - 1.54) < 0.01; });
  ASSERT_NE(down, t.end()) << "the housing never went down to the leaf";
  ASSERT_NE(down, t.begin());
  const auto before = std::prev(down), through = std::next(down);
  ASSERT_NE(through, t.end());
  EXPECT_NEAR(before->first, -0.30 + 0.55 - 0.05 - 0.02, 0.03);   // beside the leaf (2 samples: 1.8 cm)
  EXPECT_NEAR(through->first, -0.18 + 0.55 + 0.05 + 0.15, 0.03);  // through it
  EXPECT_TRUE(std::isnan(through->second));                       // at the leaf's depth
  ASSERT_NE(std::next(through), t.end());
  EXPECT_NEAR(std::next(through)->second, 1.2, 1e-9);  // up again
  EXPECT_NEAR(t.back().first, 0.35, 1e-9);             // and back to the rest extension
  EXPECT_NEAR(rig.fake.extension(), 0.35, 1e-9);
}

TEST(TopicHarvestPlant, NothingToSweepOverBareGroundOrWithoutARestAboveThePlants) {
  {
    Rig rig(searchParams());
    FrameStream frames(rig.fake, false);
    HarvestActions actions(rig.plant, actionParams());
    EXPECT_FALSE(actions.searchUnderLeaves(kNever));
    EXPECT_EQ(actions.leafSearches(), 1);
    EXPECT_EQ(actions.leafSweeps(), 0);
  }
  HarvestActionParams params = actionParams();
  params.arm.rest_depth_m = 0.0;  // the stack does not know where the arm clears the plants
  Rig rig(searchParams(), params);
  FrameStream frames(rig.fake, true);
  HarvestActions actions(rig.plant, params);
  EXPECT_FALSE(actions.searchUnderLeaves(kNever));
  EXPECT_EQ(actions.leafSearches(), 0);
  EXPECT_TRUE(rig.fake.targets().empty());  // the arm was not moved
}

TEST(TopicHarvestPlant, TheArmGoesWhereTheRoverMoveAsksWhileTheRoverMoves) {
  TopicPlantParams params = testParams();
  params.rover_settle_s = 0.05;
  Rig rig(params);
  // The fake rover stands at 0: a move of 0 m is done once the arm arrived.
  EXPECT_EQ(rig.plant.moveRover(0.0, ArmPose{0.50, std::nan("")}, kNever), MoveResult::kDone);
  EXPECT_NEAR(rig.fake.extension(), 0.50, 1e-9);
  ASSERT_EQ(rig.fake.targets().size(), 1u);
  EXPECT_NEAR(rig.fake.targets()[0].first, 0.50, 1e-9);
  EXPECT_TRUE(std::isnan(rig.fake.targets()[0].second));
  // Already there: no arm command at all.
  EXPECT_EQ(rig.plant.moveRover(0.0, ArmPose{0.50, 1.2}, kNever), MoveResult::kDone);
  EXPECT_EQ(rig.fake.targets().size(), 1u);
  const auto pose = rig.plant.armPose();
  ASSERT_TRUE(pose);
  EXPECT_NEAR(pose->extension_m, 0.50, 1e-9);
  EXPECT_NEAR(pose->depth_m, 1.2, 1e-9);
}

TEST(TopicHarvestPlant, RoverMoveWaitsForTheRoversFirstPosition) {
  // The rover node reports its position once the navigation controller's telemetry comes, which can be after the
  // machine's first move: the move starts when it comes, within the move's time.
  TopicPlantParams params = testParams();
  params.rover_settle_s = 0.05;
  Rig rig(params, actionParams(), false);
  std::thread rover([&rig] {
    ros::WallDuration(0.5).sleep();
    rig.fake.reportRoverPosition(true);
  });
  EXPECT_EQ(rig.plant.moveRover(0.0, ArmPose{}, kNever), MoveResult::kDone) << rig.plant.lastFailure();
  rover.join();

  // A position that does not come within the move's time fails the move, and says so.
  params.rover_timeout_s = 0.3;
  params.rover_timeout_per_m_s = 0.0;
  Rig silent(params, actionParams(), false);
  EXPECT_EQ(silent.plant.moveRover(0.1, ArmPose{}, kNever), MoveResult::kFailed);
  EXPECT_EQ(silent.plant.lastFailure(), "no rover position (rover/position) within 0.3 s");
}

TEST(TopicHarvestPlant, ParametersAreChecked) {
  TopicPlantParams p = testParams();
  EXPECT_EQ(TopicHarvestPlant::check(p), "");
  p.joint_max_age_s = 0.0;
  EXPECT_NE(TopicHarvestPlant::check(p).find("joint_max_age_s"), std::string::npos);
  p = testParams();
  p.effector_stamp_tolerance_s = -1.0;
  EXPECT_NE(TopicHarvestPlant::check(p).find("effector_stamp_tolerance_s"), std::string::npos);
  p = testParams();
  p.rover_tolerance_m = 0.0;
  EXPECT_NE(TopicHarvestPlant::check(p).find("rover_tolerance_m"), std::string::npos);
  // The arm's calibration and the search are the manoeuvres' parameters (one struct for the node and the bench).
  HarvestActionParams a = actionParams();
  a.arm.strip_y_m = std::nan("");
  EXPECT_NE(a.check().find("arm_y_m"), std::string::npos);
  a = actionParams();
  a.canopy.max_passes = 0;
  EXPECT_NE(a.check().find("search_max_passes"), std::string::npos);
}

}  // namespace
}  // namespace control
}  // namespace cotton_harvester

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_topic_harvest_plant");
  ros::NodeHandle nh;
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
