#include <cmath>

#include <gtest/gtest.h>

#include "cotton_harvester/control/pick_capture.h"

using namespace cotton_harvester::control;

namespace {

/// Holds the intake at `at` with the vacuum as given for `seconds` in 20 ms steps; returns the bolls taken.
std::vector<int> hold(PickCapture& capture, const Point3& at, bool vacuum, double seconds) {
  std::vector<int> taken;
  for (int i = 0; i < static_cast<int>(std::lround(seconds / 0.02)); ++i)
    for (int index : capture.update(at, vacuum, 0.02)) taken.push_back(index);
  return taken;
}

}  // namespace

TEST(PickCapture, TakesABollHeldWithinTheRadiusForThePickTime) {
  PickCapture capture;  // 4 cm, 0.8 s
  const int near = capture.addBoll({0.5, 0.1, 1.0});
  const int far = capture.addBoll({0.5, 0.3, 1.0});
  EXPECT_TRUE(hold(capture, {0.5, 0.13, 1.0}, true, 0.7).empty());  // 3 cm away, not yet long enough
  const std::vector<int> taken = hold(capture, {0.5, 0.13, 1.0}, true, 0.2);
  ASSERT_EQ(taken.size(), 1u);
  EXPECT_EQ(taken[0], near);
  EXPECT_TRUE(capture.taken(near));
  EXPECT_FALSE(capture.taken(far));
  EXPECT_EQ(capture.remaining(), 1);
  // A taken boll leaves the world: it is never taken twice.
  EXPECT_TRUE(hold(capture, {0.5, 0.1, 1.0}, true, 2.0).empty());
}

TEST(PickCapture, MissesOutsideTheRadiusWithoutVacuumOrWithABreak) {
  PickCapture capture;
  const int boll = capture.addBoll({0.0, 0.0, 1.0});
  EXPECT_TRUE(hold(capture, {0.0, 0.05, 1.0}, true, 3.0).empty());  // 5 cm: outside
  EXPECT_TRUE(hold(capture, {0.0, 0.0, 1.0}, false, 3.0).empty());  // on it, vacuum off
  EXPECT_TRUE(hold(capture, {0.0, 0.0, 1.0}, true, 0.5).empty());   // 0.5 s ...
  EXPECT_TRUE(hold(capture, {0.0, 0.0, 1.0}, false, 0.1).empty());  // ... a break ...
  EXPECT_TRUE(hold(capture, {0.0, 0.0, 1.0}, true, 0.5).empty());   // ... starts over
  EXPECT_FALSE(capture.taken(boll));
  EXPECT_EQ(hold(capture, {0.0, 0.0, 1.0}, true, 0.4).size(), 1u);
}

TEST(PickCapture, BadInputTakesNothingAndBadParametersAreRefused) {
  PickCapture capture;
  capture.addBoll({0.0, 0.0, 1.0});
  for (int i = 0; i < 100; ++i) EXPECT_TRUE(capture.update({NAN, 0.0, 1.0}, true, 0.02).empty());
  EXPECT_TRUE(capture.update({0.0, 0.0, 1.0}, true, -1.0).empty());
  EXPECT_FALSE(capture.taken(5));
  PickCaptureParams bad;
  bad.capture_radius_m = 0.0;
  EXPECT_NE(bad.check(), "");
  EXPECT_THROW(PickCapture{bad}, std::invalid_argument);
}
