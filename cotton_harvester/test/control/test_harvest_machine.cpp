// The harvest state machine driven by scripted observations (each transition of Algorithm 1,
// retries, skips, preemption, aborts) and by a simulated row with ideal motion.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <deque>
#include <thread>

#include "cotton_harvester/control/harvest_machine.h"
#include "cotton_harvester/control/virtual_row.h"
#include "scripted_harvest_plant.h"

using namespace cotton_harvester::control;
using cotton_harvester::control::fake::IdealRowPlant;
using cotton_harvester::control::fake::ScriptedPlant;
using cotton_harvester::control::fake::SearchingPlant;

namespace {

HarvestObservation frame(std::vector<Point3> bolls, Point3 effector = Point3{0.0, 0.0, 0.8}) {
  HarvestObservation observation;
  for (const auto& p : bolls) observation.bolls.push_back(BollSighting{p, 0.9, true});
  observation.end_effector = effector;
  return observation;
}

HarvestParams shortRow() {
  HarvestParams params;
  params.row_length_m = 0.6;  // two pass-on steps of 0.3 m
  return params;
}

std::vector<std::string> visited(HarvestMachine& machine) {
  std::vector<std::string> states;
  for (const auto& record : machine.machine().status().history) states.push_back(record.state);
  return states;
}

}  // namespace

TEST(HarvestMachine, NoBollsPassesOnToTheRowEnd) {
  ScriptedPlant plant;
  HarvestMachine machine(plant, shortRow());
  EXPECT_EQ(machine.run(), "finished");
  EXPECT_EQ(plant.actions, (std::vector<std::string>{"rover", "rover"}));
  EXPECT_DOUBLE_EQ(plant.values[0], 0.3);
  EXPECT_EQ(visited(machine),
            (std::vector<std::string>{"OBSERVE", "PASS_ON", "OBSERVE", "PASS_ON", "OBSERVE", "PASS_ON"}));
  EXPECT_EQ(machine.machine().status().history.back().next, "-> finished");
  EXPECT_NEAR(machine.counts().distance_m, 0.6, 1e-12);
  // The moves are the manoeuvres': the arm goes to its rest extension while the rover drives.
  for (const auto& move : plant.only("rover"))
    EXPECT_EQ(move.arm.extension_m, HarvestActionParams().arm.rest_extension_m);
}

TEST(HarvestMachine, SearchesUnderTheLeavesOnceAPlaceBeforePassingOn) {
  SearchingPlant plant;
  plant.sweep_at = {0.0};  // leaves to sweep at the start only
  HarvestParams params = shortRow();
  params.search_under_leaves = true;
  params.search_spacing_m = 0.2;
  params.row_length_m = 0.4;
  HarvestMachine machine(plant, params);
  EXPECT_EQ(machine.run(), "finished");
  // Searched at every place it stopped at, the row's end too, once; passing on moves by the search spacing.
  ASSERT_EQ(plant.searched_at.size(), 3u);
  EXPECT_NEAR(plant.searched_at[0], 0.0, 1e-9);
  EXPECT_NEAR(plant.searched_at[1], 0.2, 1e-9);
  EXPECT_NEAR(plant.searched_at[2], 0.4, 1e-9);
  EXPECT_EQ(plant.actions, (std::vector<std::string>{"sweep", "rover", "rover"}));
  EXPECT_DOUBLE_EQ(plant.values[0], 0.2);
  // A sweep is followed by a new frame; a place with nothing to sweep passes on at once.
  EXPECT_EQ(visited(machine),
            (std::vector<std::string>{"OBSERVE", "SEARCH_LEAVES", "OBSERVE", "PASS_ON", "OBSERVE", "SEARCH_LEAVES",
                                      "PASS_ON", "OBSERVE", "SEARCH_LEAVES", "PASS_ON"}));
}

TEST(HarvestMachine, ABollFoundUnderTheLeavesIsPicked) {
  SearchingPlant plant;
  plant.sweep_at = {0.0};
  plant.revealed = frame({{0.15, 0.0, 0.8}});  // under the swept leaf, in line with the end effector
  HarvestParams params = shortRow();
  params.search_under_leaves = true;
  HarvestMachine machine(plant, params);
  EXPECT_EQ(machine.run(), "finished");
  ASSERT_GE(plant.actions.size(), 2u);
  EXPECT_EQ(plant.actions[0], "sweep");
  EXPECT_EQ(plant.actions[1], "pick");
  EXPECT_EQ(machine.counts().pick_attempts, 1);
  // Without the search the plant is never asked.
  SearchingPlant plain;
  plain.sweep_at = {0.0};
  HarvestMachine paper(plain, shortRow());
  EXPECT_EQ(paper.run(), "finished");
  EXPECT_TRUE(plain.searched_at.empty());
}

TEST(HarvestMachine, SearchSpacingIsChecked) {
  HarvestParams params;
  params.search_spacing_m = 0.0;
  EXPECT_NE(params.check(), "");
}

TEST(HarvestMachine, EachTransitionFromScriptedObservations) {
  struct Case {
    Point3 boll;
    const char* state;
    const char* action;
    double value;
  };
  const Case cases[] = {
      {{0.1, 0.25, 0.9}, "MOVE_FORWARD", "rover", 0.25},   // Yb > Ym
      {{0.1, -0.2, 0.9}, "MOVE_BACKWARD", "rover", -0.2},  // Yb < Ym
      {{0.1, 0.0, 0.6}, "ARM_UP", "arm", 0.6},             // aligned, Zm > Zb
      {{0.1, 0.0, 1.0}, "ARM_DOWN", "arm", 1.0},           // aligned, Zm < Zb
      {{0.15, 0.0, 0.8}, "PICK", "pick", 0.15},            // aligned, within 37 cm
      {{0.1, 0.9, 0.9}, "MOVE_FORWARD", "rover", 0.5},     // clamped to max_rover_step_m
  };
  for (const auto& c : cases) {
    ScriptedPlant plant;
    plant.frames.push_back(frame({c.boll}));
    HarvestMachine machine(plant, shortRow());
    EXPECT_EQ(machine.run(), "finished");
    ASSERT_FALSE(plant.actions.empty());
    EXPECT_EQ(plant.actions[0], c.action) << c.state;
    EXPECT_DOUBLE_EQ(plant.values[0], c.value) << c.state;
    const auto states = visited(machine);
    ASSERT_GE(states.size(), 3u);
    EXPECT_EQ(states[0], "OBSERVE");
    EXPECT_EQ(states[1], c.state);
    EXPECT_EQ(states[2], "OBSERVE") << "every state returns to state 0";
  }
}

TEST(HarvestMachine, NearestReachableBollIsChosen) {
  ScriptedPlant plant;
  HarvestObservation observation = frame({{0.0, 0.3, 1.0}, {0.0, 0.1, 0.7}, {0.0, -0.05, 0.5}});
  observation.bolls[2].reachable = false;  // the closest one is out of the workspace
  plant.frames.push_back(observation);
  HarvestMachine machine(plant, shortRow());
  machine.run();
  EXPECT_EQ(plant.actions[0], "rover");
  EXPECT_DOUBLE_EQ(plant.values[0], 0.1);  // the boll at 0.71 m, not the one at 1.04 m
}

TEST(HarvestMachine, SuccessfulPickIsCounted) {
  ScriptedPlant plant;
  plant.frames.push_back(frame({{0.1, 0.0, 0.8}}));
  plant.frames.push_back(frame({}));  // gone after the pick
  HarvestParams params = shortRow();
  params.bolls_present = 1;
  HarvestMachine machine(plant, params);
  EXPECT_EQ(machine.run(), "finished");
  const HarvestCounts counts = machine.counts();
  EXPECT_EQ(counts.detected, 1);
  EXPECT_EQ(counts.reached, 1);
  EXPECT_EQ(counts.picked, 1);
  EXPECT_EQ(counts.skipped, 0);
  EXPECT_EQ(counts.pick_attempts, 1);
  EXPECT_DOUBLE_EQ(*computeMetrics(counts).action_success_pct, 100.0);
}

TEST(HarvestMachine, FailedPicksAreRetriedThenTheBollIsSkipped) {
  ScriptedPlant plant;
  for (int i = 0; i < 4; ++i) plant.frames.push_back(frame({{0.1, 0.0, 0.8}}));  // it stays on the plant
  HarvestParams params = shortRow();
  params.tracker.max_pick_attempts = 3;
  HarvestMachine machine(plant, params);
  EXPECT_EQ(machine.run(), "finished");
  EXPECT_EQ(plant.actions, (std::vector<std::string>{"pick", "pick", "pick", "rover", "rover"}));
  const HarvestCounts counts = machine.counts();
  EXPECT_EQ(counts.pick_attempts, 3);
  EXPECT_EQ(counts.skipped, 1);
  EXPECT_EQ(counts.picked, 0);
  EXPECT_EQ(counts.reached, 1);
}

TEST(HarvestMachine, BollThatCannotBeAlignedIsSkipped) {
  ScriptedPlant plant;
  // The rover "moves" but the boll stays 20 cm ahead in every frame (wheel slip).
  for (int i = 0; i < 10; ++i) plant.frames.push_back(frame({{0.1, 0.2, 0.8}}));
  HarvestParams params = shortRow();
  params.row_length_m = 1.0;
  params.tracker.max_align_moves = 4;
  params.tracker.match_radius_m = 10.0;  // the same boll despite the rover's odometry
  HarvestMachine machine(plant, params);
  EXPECT_EQ(machine.run(), "finished");
  // Four moves towards it, then it is skipped and the rover passes on (0.8 m + 0.3 m > 1 m: row end).
  EXPECT_EQ(plant.values, (std::vector<double>{0.2, 0.2, 0.2, 0.2, 0.3}));
  EXPECT_EQ(machine.counts().skipped, 1);
  EXPECT_EQ(machine.counts().reached, 0);
}

TEST(HarvestMachine, OutOfReachBollIsSkippedAndTheRowContinues) {
  ScriptedPlant plant;
  plant.frames.push_back(frame({{0.5, 0.0, 0.8}}));  // aligned but 50 cm across
  HarvestMachine machine(plant, shortRow());
  EXPECT_EQ(machine.run(), "finished");
  EXPECT_EQ(plant.actions, (std::vector<std::string>{"rover", "rover"}));
  EXPECT_EQ(machine.counts().skipped, 1);
}

TEST(HarvestMachine, PreemptionDuringAMove) {
  ScriptedPlant plant;
  plant.block_rover = true;
  HarvestMachine machine(plant, shortRow());
  std::string outcome;
  std::thread runner([&] { outcome = machine.run(); });
  while (!plant.blocking) std::this_thread::yield();
  const auto status = machine.machine().status();
  EXPECT_TRUE(status.running);
  EXPECT_EQ(status.active_state, "PASS_ON");
  machine.machine().requestPreempt();
  runner.join();
  EXPECT_EQ(outcome, "preempted");
  EXPECT_FALSE(machine.machine().status().running);
}

TEST(HarvestMachine, NoFramesAborts) {
  ScriptedPlant plant;
  for (int i = 0; i < 20; ++i) plant.frames.push_back(std::nullopt);
  HarvestParams params = shortRow();
  params.max_missed_observations = 5;
  HarvestMachine machine(plant, params);
  EXPECT_EQ(machine.run(), "aborted");
  EXPECT_TRUE(plant.actions.empty());
  EXPECT_EQ(machine.machine().status().transitions, 5u);
  EXPECT_EQ(machine.abortReason(), "5 frames in a row unusable, the last: no frame");
}

TEST(HarvestMachine, BollsWithoutEndEffectorAreRejected) {
  ScriptedPlant plant;
  HarvestObservation observation = frame({{0.1, 0.0, 0.8}});
  observation.end_effector.reset();
  for (int i = 0; i < 3; ++i) plant.frames.push_back(observation);
  HarvestParams params = shortRow();
  params.max_missed_observations = 3;
  HarvestMachine machine(plant, params);
  EXPECT_EQ(machine.run(), "aborted");
  EXPECT_EQ(machine.rejectedFrames(), 3);
  EXPECT_EQ(machine.abortReason(), "3 frames in a row unusable, the last: no end effector in the frame");
}

TEST(HarvestMachine, ActionsThatKeepFailingAbort) {
  ScriptedPlant plant;
  plant.result = MoveResult::kFailed;
  HarvestMachine machine(plant, shortRow());
  EXPECT_EQ(machine.run(), "aborted");
  EXPECT_EQ(plant.actions.size(), 3u);
  EXPECT_EQ(machine.abortReason(), "3 rover/arm actions failed in a row");
}

TEST(HarvestMachine, NanSightingsAreIgnored) {
  ScriptedPlant plant;
  plant.frames.push_back(frame({{std::nan(""), 0.0, 0.8}}));
  HarvestMachine machine(plant, shortRow());
  EXPECT_EQ(machine.run(), "finished");
  EXPECT_EQ(machine.counts().detected, 0);
}

TEST(HarvestParams, CheckNamesTheKey) {
  HarvestParams params;
  EXPECT_EQ(params.check(), "");
  params.tracker.max_pick_attempts = 0;
  EXPECT_NE(params.check().find("max_pick_attempts"), std::string::npos);
  params = HarvestParams();
  params.row_length_m = -1.0;
  EXPECT_NE(params.check().find("row_length_m"), std::string::npos);
  params = HarvestParams();
  params.actions.pick_dwell_s = 0.0;  // the manoeuvres' parameters are the machine's too
  EXPECT_NE(params.check().find("pick_dwell_s"), std::string::npos);
  params = HarvestParams();
  params.actions.arm.rest_depth_m = 0.0;
  EXPECT_EQ(params.check(), "");
  params.search_under_leaves = true;  // the search looks from above the plants
  EXPECT_NE(params.check().find("rest_depth_m"), std::string::npos);
}

TEST(HarvestMachine, HarvestsASimulatedRowOfSixPlants) {
  VirtualRowParams row;  // 6 plants x 3 bolls, 85 % of brush passes take the boll
  IdealRowPlant plant(row);
  HarvestParams params;
  params.row_length_m = 2.4;  // the preliminary experiment's distance
  params.bolls_present = plant.row.present();
  params.actions.arm.extension_max_m = row.arm_length_m;  // the virtual arm: 0.6 m, at rest retracted
  params.actions.arm.rest_extension_m = 0.0;
  HarvestMachine machine(plant, params);
  EXPECT_EQ(machine.run(), "finished");
  const HarvestCounts counts = machine.counts();
  EXPECT_EQ(counts.bolls_present, 18);
  // The tracker counts a pick when the boll it aimed at is gone. The seeded row has two bolls 6 cm
  // apart that one brush pass takes together: the row lost one more boll than the tracker saw picked.
  const int removed = 18 - plant.row.remaining();
  EXPECT_LE(counts.picked, removed);
  EXPECT_GE(counts.picked, removed - 1);
  EXPECT_GE(counts.picked, 15);
  EXPECT_EQ(counts.detected, 18);
  EXPECT_LE(counts.picked + counts.skipped, counts.detected);
  EXPECT_GE(counts.reached, counts.picked);
}

// A boll hidden once the rover stands over it: with the tracker's memory the machine still aims at it from where it
// was last seen (the arm goes down to it); without, it passes on as Algorithm 1 does.
TEST(HarvestMachine, HiddenTargetIsAimedAtFromMemory) {
  for (int remember : {0, 2}) {
    ScriptedPlant plant;
    plant.frames.push_back(frame({{0.1, 0.2, 1.0}}));  // ahead: move forward 0.2 m; the next frames show no boll
    plant.frames.push_back(frame({}));
    plant.frames.push_back(frame({}));
    HarvestParams params = shortRow();
    params.remember_target_frames = remember;
    HarvestMachine machine(plant, params);
    machine.run();
    ASSERT_GE(plant.actions.size(), 2u) << remember;
    EXPECT_EQ(plant.actions[0], "rover");
    EXPECT_NEAR(plant.values[0], 0.2, 1e-9);
    if (remember == 0) {
      EXPECT_EQ(plant.actions[1], "rover");  // pass on
      EXPECT_NEAR(plant.values[1], params.pass_step_m, 1e-9);
    } else {
      EXPECT_EQ(plant.actions[1], "arm");  // aligned along the row: down to the remembered depth
      EXPECT_NEAR(plant.values[1], 1.0, 1e-9);
    }
  }
}

// The along-row order takes the rearmost pending boll (a sweep in the direction of travel), and among bolls of one
// stop the nearest from the lens; the range order (eq. 6) takes the highest wherever it is.
TEST(HarvestMachine, AlongRowOrderTakesTheRearmostBoll) {
  for (TargetOrder order : {TargetOrder::kRange, TargetOrder::kAlongRow}) {
    ScriptedPlant plant;
    plant.frames.push_back(frame({{0.0, 0.3, 0.6}, {0.0, -0.2, 1.2}, {0.0, -0.21, 1.0}, {0.0, 0.1, 0.9}}));
    HarvestParams params = shortRow();
    params.tracker.order = order;
    HarvestMachine machine(plant, params);
    machine.run();
    ASSERT_FALSE(plant.actions.empty());
    EXPECT_EQ(plant.actions[0], "rover");
    // kRange: the boll at 0.67 m from the lens (y 0.3); kAlongRow: y -0.21 (within 3 cm of -0.2, nearer the lens).
    EXPECT_NEAR(plant.values[0], order == TargetOrder::kRange ? 0.3 : -0.21, 1e-9);
  }
}

// With keep_target, the boll being worked on stays the target when the next frame ranks another first (here: the
// target is hidden once the rover stands over it and a boll further back appears): no turning back and forth.
TEST(HarvestMachine, KeptTargetIsFinishedBeforeAnotherIsStarted) {
  for (bool keep : {false, true}) {
    ScriptedPlant plant;
    plant.frames.push_back(frame({{0.1, 0.2, 1.0}}));    // ahead: forward 0.2 m
    plant.frames.push_back(frame({{0.0, -0.25, 1.1}}));  // target hidden, another one behind
    plant.frames.push_back(frame({{0.1, 0.0, 1.0}, {0.0, -0.25, 1.1}}));
    HarvestParams params = shortRow();
    params.tracker.order = TargetOrder::kAlongRow;
    params.remember_target_frames = 2;
    params.keep_target = keep;
    HarvestMachine machine(plant, params);
    machine.run();
    ASSERT_GE(plant.actions.size(), 2u) << keep;
    EXPECT_EQ(plant.actions[0], "rover");
    if (keep) {
      EXPECT_EQ(plant.actions[1], "arm");  // down to the remembered target, the rover stays
      EXPECT_NEAR(plant.values[1], 1.0, 1e-9);
    } else {
      EXPECT_EQ(plant.actions[1], "rover");  // turns back to the other boll
      EXPECT_NEAR(plant.values[1], -0.25, 1e-9);
    }
  }
  HarvestParams bad = shortRow();
  bad.tracker.along_row_band_m = -0.1;
  EXPECT_NE(bad.check().find("along_row_band_m"), std::string::npos);
}

// revisit_pending: a boll two frames showed reachable and the next frames hide is aimed at from the tracker's memory
// before the rover passes on; without it (and without the target's memory) the rover passes on.
TEST(HarvestMachine, HiddenPendingBollIsRevisitedBeforePassingOn) {
  for (bool revisit : {false, true}) {
    ScriptedPlant plant;
    plant.frames.push_back(frame({{0.1, 0.2, 1.0}}));  // ahead: forward 0.2 m
    plant.frames.push_back(frame({{0.1, 0.0, 1.0}}));  // aligned: the arm down to 1.0 m; then hidden for good
    for (int i = 0; i < 12; ++i) plant.frames.push_back(frame({}));
    HarvestParams params = shortRow();
    params.revisit_pending = revisit;
    HarvestMachine machine(plant, params);
    EXPECT_EQ(machine.run(), "finished");
    ASSERT_GE(plant.actions.size(), 3u) << revisit;
    EXPECT_EQ(plant.actions[0], "rover");
    EXPECT_EQ(plant.actions[1], "arm");
    if (revisit) {
      EXPECT_EQ(plant.actions[2], "arm");  // aimed at from memory (the scripted arm never gets there)
      EXPECT_NEAR(plant.values[2], 1.0, 1e-9);
      const auto tracks = machine.tracks();
      ASSERT_EQ(tracks.size(), 1u);
      EXPECT_EQ(tracks[0].fate, BollFate::kSkipped);  // after max_align_moves
    } else {
      EXPECT_EQ(plant.actions[2], "rover");  // pass on
      EXPECT_NEAR(plant.values[2], params.pass_step_m, 1e-9);
    }
  }
}
