// The miss-cause classification of the harvest scorer: each cause from hand-made records and tracks.
#include <gtest/gtest.h>

#include "cotton_harvester_sim/miss_causes.h"

using namespace cotton_harvester;
using sim::MissCause;

namespace {

sim::BollRecord seenBoll() {
  sim::BollRecord r;
  r.reachable = true;
  r.frames_in_view = 5;
  r.frames_detected = 4;
  r.frames_detected_reachable = 3;
  r.max_visible_fraction = 1.0;
  r.sighted = true;
  r.along_row_m = 1.20;
  r.across_m = -0.10;
  r.depth_m = 1.50;
  return r;
}

control::TrackedBoll trackAt(double along, double across, double depth, control::BollFate fate) {
  control::TrackedBoll t;
  t.id = 1;
  t.along_row_m = along;
  t.across_m = across;
  t.depth_m = depth;
  t.fate = fate;
  return t;
}

}  // namespace

TEST(MissCauses, TruthAndPerceptionCauses) {
  const control::TrackerParams tp;
  sim::BollRecord r = seenBoll();
  r.captured = true;
  EXPECT_EQ(sim::classifyMiss(r, {}, tp), MissCause::kCaptured);
  r = seenBoll();
  r.reachable = false;
  EXPECT_EQ(sim::classifyMiss(r, {}, tp), MissCause::kOutOfWorkspace);
  r = seenBoll();
  r.frames_in_view = 0;
  EXPECT_EQ(sim::classifyMiss(r, {}, tp), MissCause::kNeverInView);
  r = seenBoll();
  r.frames_detected = 0;
  r.max_visible_fraction = 0.3;
  EXPECT_EQ(sim::classifyMiss(r, {}, tp), MissCause::kOccluded);
  r.max_visible_fraction = 0.6;
  EXPECT_EQ(sim::classifyMiss(r, {}, tp), MissCause::kNotDetected);
  // No camera position along the row sees half of it: hidden from the row, whatever the frames taken showed.
  r.row_best_visible_fraction = 0.2;
  EXPECT_EQ(sim::classifyMiss(r, {}, tp), MissCause::kHiddenFromRow);
  r.max_visible_fraction = 0.0;
  EXPECT_EQ(sim::classifyMiss(r, {}, tp), MissCause::kHiddenFromRow);
  // Seen from some position the camera never took: occluded in the frames taken, not hidden from the row.
  r.row_best_visible_fraction = 0.7;
  EXPECT_EQ(sim::classifyMiss(r, {}, tp), MissCause::kOccluded);
  r = seenBoll();
  r.row_best_visible_fraction = 0.1;  // detected all the same (e.g. after a leaf was pushed): not hidden
  EXPECT_NE(sim::classifyMiss(r, {}, tp), MissCause::kHiddenFromRow);
  r = seenBoll();
  r.frames_detected_reachable = 0;
  EXPECT_EQ(sim::classifyMiss(r, {}, tp), MissCause::kJudgedUnreachable);
}

TEST(MissCauses, TrackFates) {
  control::TrackerParams tp;
  tp.max_pick_attempts = 3;
  tp.max_align_moves = 8;
  const sim::BollRecord r = seenBoll();
  // No track within the match radius (6 cm): the stack never held it.
  EXPECT_EQ(sim::classifyMiss(r, {trackAt(1.30, -0.10, 1.50, control::BollFate::kPending)}, tp),
            MissCause::kJudgedUnreachable);
  EXPECT_EQ(sim::classifyMiss(r, {trackAt(1.22, -0.10, 1.50, control::BollFate::kPending)}, tp),
            MissCause::kPassedOver);
  EXPECT_EQ(sim::classifyMiss(r, {trackAt(1.20, -0.11, 1.51, control::BollFate::kPicked)}, tp),
            MissCause::kBelievedPicked);
  control::TrackedBoll t = trackAt(1.20, -0.10, 1.50, control::BollFate::kSkipped);
  t.pick_attempts = 3;
  EXPECT_EQ(sim::classifyMiss(r, {t}, tp), MissCause::kPicksFailed);
  t.pick_attempts = 1;
  t.align_moves = 9;
  EXPECT_EQ(sim::classifyMiss(r, {t}, tp), MissCause::kAlignGaveUp);
  t.align_moves = 2;
  EXPECT_EQ(sim::classifyMiss(r, {t}, tp), MissCause::kJudgedOutOfReach);
  // The nearest of two tracks is the boll's.
  const control::TrackedBoll far = trackAt(1.25, -0.10, 1.50, control::BollFate::kPicked);
  const control::TrackedBoll near = trackAt(1.21, -0.10, 1.50, control::BollFate::kPending);
  EXPECT_EQ(sim::classifyMiss(r, {far, near}, tp), MissCause::kPassedOver);
}

TEST(MissCauses, TableCountsMissesOnly) {
  sim::MissTable a, b;
  a.add(MissCause::kCaptured);
  a.add(MissCause::kOccluded);
  b.add(MissCause::kPicksFailed);
  b.add(MissCause::kOccluded);
  a.add(b);
  EXPECT_EQ(a.misses(), 3);
  EXPECT_EQ(a.count[static_cast<int>(MissCause::kOccluded)], 2);
  EXPECT_EQ(a.count[static_cast<int>(MissCause::kCaptured)], 1);
  EXPECT_STREQ(sim::toString(MissCause::kBelievedPicked), "believed_picked");
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
