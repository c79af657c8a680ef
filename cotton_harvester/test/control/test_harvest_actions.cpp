// The harvest manoeuvres on a fake plant that records every primitive call: the pick's sequence, the leaf clearing
// before it, the search under the leaves layer by layer from the top, the arm's rest, failures and preemption.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "cotton_harvester/control/harvest_actions.h"
#include "fake_harvest_plant.h"

using namespace cotton_harvester::control;
using cotton_harvester::control::fake::FakeHarvestPlant;
using cotton_harvester::control::fake::Leaf;

namespace {

using Names = std::vector<std::string>;

HarvestPlant::Preempted preemptedOf(const FakeHarvestPlant& plant) {
  return [&plant] { return plant.preemptRequested(); };
}

void expectArm(const FakeHarvestPlant::Call& call, double extension, double depth, double tolerance = 1e-9) {
  EXPECT_EQ(call.what, "arm");
  if (std::isnan(extension)) {
    EXPECT_TRUE(std::isnan(call.a)) << "extension " << call.a;
  } else {
    EXPECT_NEAR(call.a, extension, tolerance);
  }
  if (std::isnan(depth)) {
    EXPECT_TRUE(std::isnan(call.b)) << "depth " << call.b;
  } else {
    EXPECT_NEAR(call.b, depth, tolerance);
  }
}

const double kStays = std::nan("");

}  // namespace

TEST(HarvestActions, PickGoesOutRunsTheVacuumAndReturnsToRest) {
  FakeHarvestPlant plant;
  plant.arm = {0.20, 1.5};  // not at rest: the pick still ends at the rest extension
  HarvestActions actions(plant, HarvestActionParams());
  EXPECT_EQ(actions.pick(0.25, preemptedOf(plant)), MoveResult::kDone);
  ASSERT_EQ(plant.names(), (Names{"arm", "vacuum", "wait", "arm", "vacuum"}));
  expectArm(plant.calls[0], 0.45, kStays);  // out by the offset
  EXPECT_EQ(plant.calls[1].a, 1.0);         // vacuum on at the boll ...
  EXPECT_EQ(plant.calls[2].a, 1.0);         // ... for pick_dwell_s
  expectArm(plant.calls[3], 0.35, kStays);  // back to the rest extension with the vacuum on
  EXPECT_EQ(plant.calls[4].a, 0.0);
  EXPECT_FALSE(plant.vacuum);
  EXPECT_NEAR(plant.arm.depth_m, 1.5, 1e-12);  // the arm stays at the boll's depth
  EXPECT_EQ(actions.picksCleared(), 0);
}

TEST(HarvestActions, PickVariants) {
  HarvestActionParams params;
  params.vacuum_while_retracting = false;
  params.raise_after_pick = true;
  params.pick_dwell_s = 0.5;
  FakeHarvestPlant plant;
  HarvestActions actions(plant, params);
  EXPECT_EQ(actions.pick(0.9, preemptedOf(plant)), MoveResult::kDone);
  ASSERT_EQ(plant.names(), (Names{"arm", "vacuum", "wait", "vacuum", "arm", "arm"}));
  expectArm(plant.calls[0], 0.70, kStays);  // clamped into the horizontal travel
  EXPECT_EQ(plant.calls[2].a, 0.5);
  EXPECT_EQ(plant.calls[3].a, 0.0);  // off at the boll
  expectArm(plant.calls[4], 0.35, kStays);
  expectArm(plant.calls[5], kStays, 1.20);  // up to the rest depth at once
}

TEST(HarvestActions, PickFailuresAndPreemption) {
  {
    FakeHarvestPlant plant;
    plant.fail_arm_move = 0;  // the way out
    HarvestActions actions(plant, HarvestActionParams());
    EXPECT_EQ(actions.pick(0.1, preemptedOf(plant)), MoveResult::kFailed);
    EXPECT_EQ(plant.names(), (Names{"arm"}));  // no vacuum without the arm at the boll
  }
  {
    FakeHarvestPlant plant;
    plant.fail_arm_move = 1;  // the way back
    HarvestActions actions(plant, HarvestActionParams());
    EXPECT_EQ(actions.pick(0.1, preemptedOf(plant)), MoveResult::kFailed);
    EXPECT_EQ(plant.names(), (Names{"arm", "vacuum", "wait", "arm", "vacuum"}));
    EXPECT_FALSE(plant.vacuum);
  }
  {
    FakeHarvestPlant plant;
    plant.preempt_after_calls = 3;  // during the dwell
    HarvestActions actions(plant, HarvestActionParams());
    EXPECT_EQ(actions.pick(0.1, preemptedOf(plant)), MoveResult::kPreempted);
    EXPECT_EQ(plant.names(), (Names{"arm", "vacuum", "wait", "vacuum"}));
    EXPECT_FALSE(plant.vacuum);
  }
  FakeHarvestPlant plant;
  HarvestActions actions(plant, HarvestActionParams());
  EXPECT_EQ(actions.pick(std::nan(""), preemptedOf(plant)), MoveResult::kFailed);
  EXPECT_TRUE(plant.calls.empty());
}

// A leaf 5 cm above the boll's top between the housing and the boll: the arm goes up 6 cm, through the leaf 4 cm past
// the boll, back to 12 cm short of it, down again; the new frame shows the boll 2 cm further out and 3 cm deeper.
TEST(HarvestActions, LeavesOverTheBollAreSweptAsideAndTheBollLocatedAgain) {
  HarvestActionParams params;
  params.clear_leaves_before_pick = true;
  FakeHarvestPlant plant;
  plant.arm = {0.35, 1.60};                          // housing at camera x -0.20, at the boll's top
  plant.leaves = {{-0.12, 0.0, -0.04, 0.04, 1.55}};  // over the approach to the boll at x 0
  HarvestObservation after;
  after.bolls.push_back(BollSighting{Point3{0.02, 0.0, 1.63}, 0.9, true});
  plant.frames.push_back(after);
  HarvestActions actions(plant, params);
  EXPECT_EQ(actions.pick(0.20, preemptedOf(plant)), MoveResult::kDone);
  ASSERT_EQ(plant.names(),
            (Names{"cloud", "arm", "arm", "arm", "arm", "observe", "arm", "arm", "vacuum", "wait", "arm", "vacuum"}));
  expectArm(plant.calls[1], kStays, 1.54);  // up by leaf_clearance_m
  expectArm(plant.calls[2], 0.59, kStays);  // through the leaf, clear_overshoot_m past the boll
  expectArm(plant.calls[3], 0.43, kStays);  // back to clear_standoff_m short of it
  expectArm(plant.calls[4], kStays, 1.60);  // down to the boll's top again
  expectArm(plant.calls[6], kStays, 1.63);  // the re-located boll is deeper
  expectArm(plant.calls[7], 0.57, kStays);  // and further out
  EXPECT_EQ(actions.picksCleared(), 1);
  EXPECT_EQ(actions.picksRedetected(), 1);
}

TEST(HarvestActions, NoSweepWithoutLeavesOverTheApproachOrWhenSwitchedOff) {
  HarvestActionParams params;
  params.clear_leaves_before_pick = true;
  FakeHarvestPlant plant;
  plant.arm = {0.35, 1.60};
  plant.leaves = {{-0.12, 0.0, -0.04, 0.04, 1.30}};  // 30 cm above the boll: no leaf on it
  HarvestActions actions(plant, params);
  EXPECT_EQ(actions.pick(0.20, preemptedOf(plant)), MoveResult::kDone);
  EXPECT_EQ(plant.names(), (Names{"cloud", "arm", "vacuum", "wait", "arm", "vacuum"}));
  EXPECT_EQ(actions.picksCleared(), 0);

  FakeHarvestPlant off;
  off.arm = {0.35, 1.60};
  off.leaves = {{-0.12, 0.0, -0.04, 0.04, 1.55}};
  HarvestActions plain(off, HarvestActionParams());  // clear_leaves_before_pick false: the cloud is not even asked
  EXPECT_EQ(plain.pick(0.20, preemptedOf(off)), MoveResult::kDone);
  EXPECT_EQ(off.names(), (Names{"arm", "vacuum", "wait", "arm", "vacuum"}));
}

// Two leaves in the arm's strip, at 1.40 m and 1.60 m: swept one after the other from the top, a frame after each,
// then the arm back to its rest extension.
TEST(HarvestActions, SearchSweepsTheLayersFromTheTopAndReturnsToRest) {
  FakeHarvestPlant plant;
  plant.arm = {0.50, 1.0};  // above the rest depth: it stays up there
  plant.leaves = {{-0.30, -0.18, -0.04, 0.04, 1.40}, {-0.10, 0.02, -0.04, 0.04, 1.60}};
  HarvestActions actions(plant, HarvestActionParams());
  const auto result = actions.searchUnderLeaves(preemptedOf(plant));
  ASSERT_TRUE(result);
  EXPECT_EQ(*result, MoveResult::kDone);
  ASSERT_EQ(plant.names(), (Names{"arm", "observe", "cloud", "arm", "arm", "arm", "arm", "observe", "cloud", "arm",
                                  "arm", "arm", "arm", "observe", "cloud", "arm"}));
  expectArm(plant.calls[0], 0.35, kStays);
  // First layer: beside it above the plants (housing half side + 2 cm), down to 1 cm above its top, through it to
  // push_m past its far edge, up to the rest depth. Points sit on pixels 4-6 mm apart: 1 cm tolerance.
  expectArm(plant.calls[3], -0.30 + 0.55 - 0.05 - 0.02, kStays, 0.01);
  expectArm(plant.calls[4], kStays, 1.39, 0.01);
  expectArm(plant.calls[5], -0.18 + 0.55 + 0.05 + 0.15, kStays, 0.01);
  expectArm(plant.calls[6], kStays, 1.20);
  // The second, deeper layer; its far end is beyond the travel.
  expectArm(plant.calls[9], -0.10 + 0.55 - 0.05 - 0.02, kStays, 0.01);
  expectArm(plant.calls[10], kStays, 1.59, 0.01);
  expectArm(plant.calls[11], 0.70, kStays);
  expectArm(plant.calls[15], 0.35, kStays);
  EXPECT_EQ(actions.leafSearches(), 1);
  EXPECT_EQ(actions.leafSweeps(), 2);
}

TEST(HarvestActions, SearchStartsAtTheRestAndFindsNothingOverBareGround) {
  FakeHarvestPlant plant;
  plant.arm = {0.50, 1.5};  // deeper than the rest: up first
  HarvestActions actions(plant, HarvestActionParams());
  EXPECT_FALSE(actions.searchUnderLeaves(preemptedOf(plant)));
  EXPECT_EQ(plant.names(), (Names{"arm", "observe", "cloud", "arm"}));
  expectArm(plant.calls[0], 0.35, 1.20);
  EXPECT_EQ(actions.leafSearches(), 1);
  EXPECT_EQ(actions.leafSweeps(), 0);

  HarvestActionParams no_rest;
  no_rest.arm.rest_depth_m = 0.0;  // no depth known above the plants: nothing to look from
  FakeHarvestPlant idle;
  HarvestActions without(idle, no_rest);
  EXPECT_FALSE(without.searchUnderLeaves(preemptedOf(idle)));
  EXPECT_TRUE(idle.calls.empty());
}

TEST(HarvestActions, SearchFailuresAndPreemption) {
  const std::vector<Leaf> leaf = {{-0.30, -0.18, -0.04, 0.04, 1.40}};
  {
    FakeHarvestPlant plant;
    plant.leaves = leaf;
    plant.preempt_after_calls = 5;  // during the first sweep
    HarvestActions actions(plant, HarvestActionParams());
    const auto result = actions.searchUnderLeaves(preemptedOf(plant));
    ASSERT_TRUE(result);
    EXPECT_EQ(*result, MoveResult::kPreempted);
    EXPECT_EQ(plant.calls.size(), 5u);
  }
  {
    FakeHarvestPlant plant;
    plant.leaves = leaf;
    plant.fail_arm_move = 2;  // down beside the leaf
    HarvestActions actions(plant, HarvestActionParams());
    const auto result = actions.searchUnderLeaves(preemptedOf(plant));
    ASSERT_TRUE(result);
    EXPECT_EQ(*result, MoveResult::kFailed);
    EXPECT_EQ(actions.leafSweeps(), 0);
  }
  {
    FakeHarvestPlant plant;
    plant.frames.push_back(std::nullopt);  // no frame to look at
    HarvestActions actions(plant, HarvestActionParams());
    const auto result = actions.searchUnderLeaves(preemptedOf(plant));
    ASSERT_TRUE(result);
    EXPECT_EQ(*result, MoveResult::kFailed);
    EXPECT_EQ(actions.leafSearches(), 0);
  }
  FakeHarvestPlant plant;
  plant.leaves = leaf;
  plant.has_cloud = false;  // no cloud of the frame: nothing can be found
  HarvestActions actions(plant, HarvestActionParams());
  EXPECT_FALSE(actions.searchUnderLeaves(preemptedOf(plant)));
  EXPECT_EQ(plant.names(), (Names{"arm", "observe", "cloud", "arm"}));
}

TEST(HarvestActions, RoverMovesWithTheArmGoingToItsRest) {
  FakeHarvestPlant plant;
  plant.arm = {0.60, 1.5};
  HarvestActions actions(plant, HarvestActionParams());
  EXPECT_EQ(actions.moveRover(0.3, preemptedOf(plant)), MoveResult::kDone);
  ASSERT_EQ(plant.names(), (Names{"rover"}));
  EXPECT_EQ(plant.calls[0].a, 0.3);
  EXPECT_EQ(plant.calls[0].arm.extension_m, 0.35);
  EXPECT_EQ(plant.calls[0].arm.depth_m, 1.20);  // deeper than the rest: up while driving
  EXPECT_EQ(actions.moveRover(-0.1, preemptedOf(plant)), MoveResult::kDone);
  EXPECT_TRUE(std::isnan(plant.calls[1].arm.depth_m));  // already above the plants: the depth stays
  EXPECT_EQ(actions.moveRover(std::nan(""), preemptedOf(plant)), MoveResult::kFailed);
  EXPECT_EQ(plant.calls.size(), 2u);

  HarvestActionParams no_rest;
  no_rest.arm.rest_depth_m = 0.0;
  FakeHarvestPlant deep;
  deep.arm = {0.60, 1.8};
  HarvestActions keep_depth(deep, no_rest);
  EXPECT_EQ(keep_depth.moveRover(0.3, preemptedOf(deep)), MoveResult::kDone);
  EXPECT_TRUE(std::isnan(deep.calls[0].arm.depth_m));
  EXPECT_EQ(deep.calls[0].arm.extension_m, 0.35);
}

TEST(HarvestActions, ArmToDepthIsClampedIntoTheTravel) {
  FakeHarvestPlant plant;
  HarvestActions actions(plant, HarvestActionParams());
  EXPECT_EQ(actions.armToDepth(2.5, preemptedOf(plant)), MoveResult::kDone);
  EXPECT_EQ(actions.armToDepth(0.1, preemptedOf(plant)), MoveResult::kDone);
  EXPECT_EQ(actions.armToDepth(1.1, preemptedOf(plant)), MoveResult::kDone);
  EXPECT_EQ(actions.armToDepth(std::nan(""), preemptedOf(plant)), MoveResult::kFailed);
  ASSERT_EQ(plant.names(), (Names{"arm", "arm", "arm"}));
  expectArm(plant.calls[0], kStays, 1.93);
  expectArm(plant.calls[1], kStays, 0.30);
  expectArm(plant.calls[2], kStays, 1.1);
  plant.result = MoveResult::kFailed;
  EXPECT_EQ(actions.armToDepth(1.0, preemptedOf(plant)), MoveResult::kFailed);
}

TEST(HarvestActionParams, CheckNamesTheKey) {
  EXPECT_EQ(HarvestActionParams().check(), "");
  const auto problem = [](auto change) {
    HarvestActionParams p;
    change(p);
    return p.check();
  };
  EXPECT_NE(problem([](auto& p) { p.arm.rest_extension_m = 0.9; }).find("rest_extension_m"), std::string::npos);
  EXPECT_NE(problem([](auto& p) { p.arm.rest_depth_m = 2.5; }).find("rest_depth_m"), std::string::npos);
  EXPECT_EQ(problem([](auto& p) { p.arm.rest_depth_m = 0.0; }), "");  // none
  EXPECT_NE(problem([](auto& p) { p.arm.extension_max_m = -1.0; }).find("horizontal_max_m"), std::string::npos);
  EXPECT_NE(problem([](auto& p) { p.arm.min_depth_m = 2.0; }).find("vertical_min_m"), std::string::npos);
  EXPECT_NE(problem([](auto& p) { p.arm.strip_y_m = std::nan(""); }).find("arm_y_m"), std::string::npos);
  EXPECT_NE(problem([](auto& p) { p.arm.extension_zero_x_m = INFINITY; }).find("arm_extension_zero_x_m"),
            std::string::npos);
  EXPECT_NE(problem([](auto& p) { p.pick_dwell_s = 0.0; }).find("pick_dwell_s"), std::string::npos);
  EXPECT_NE(problem([](auto& p) { p.leaves.leaf_points_min = 0; }).find("leaf_points_min"), std::string::npos);
  EXPECT_NE(problem([](auto& p) { p.canopy.max_passes = 0; }).find("search_max_passes"), std::string::npos);
  EXPECT_NE(problem([](auto& p) { p.canopy.effector_half_m = 0.07; }).find("effector_half_m"), std::string::npos);
  FakeHarvestPlant plant;
  HarvestActionParams bad;
  bad.pick_dwell_s = -1.0;
  EXPECT_THROW({ HarvestActions rejected(plant, bad); }, std::invalid_argument);
}
