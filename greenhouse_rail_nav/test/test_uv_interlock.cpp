// The UV interlock's decisions on a simulated clock: every input keeps the lamps off when it does not permit, has
// not been heard or is stale; the lamps are on only when all permit.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "greenhouse_rail_nav/uv_interlock.h"

using greenhouse_rail_nav::atTreatmentSpeed;
using greenhouse_rail_nav::InterlockDecision;
using greenhouse_rail_nav::SpeedWindow;
using greenhouse_rail_nav::UvInterlock;

namespace {

/// The node's inputs: request (never stale), on rails, speed, people detected, people present, base, one lock.
struct Rig {
  Rig() {
    request = interlock.add({"uv_lights request", 0.0});
    rails = interlock.add({"on rails", 0.3});
    speed = interlock.add({"treatment speed", 0.3});
    detected = interlock.add({"people_detected", 0.5});
    present = interlock.add({"people_present", 0.5});
    base = interlock.add({"base stop", 0.3});
    lock = interlock.add({"lock safety/lock", 0.3});
  }
  /// Every input reports "permits" at time t.
  void allPermit(double t) {
    for (size_t i = 0; i < interlock.size(); ++i) interlock.update(i, true, t);
  }
  UvInterlock interlock;
  size_t request, rails, speed, detected, present, base, lock;
};

TEST(UvInterlock, OffUntilEveryInputWasHeard) {
  Rig r;
  InterlockDecision d = r.interlock.decide(0.0);
  EXPECT_FALSE(d.lamps_on);
  EXPECT_EQ(d.blocking.size(), 7u);
  EXPECT_EQ(d.blocking[0], "uv_lights request: never received");
  for (size_t i = 0; i + 1 < r.interlock.size(); ++i) r.interlock.update(i, true, 0.0);
  d = r.interlock.decide(0.0);
  EXPECT_FALSE(d.lamps_on);
  ASSERT_EQ(d.blocking.size(), 1u);
  EXPECT_EQ(d.blocking[0], "lock safety/lock: never received");
  r.interlock.update(r.lock, true, 0.01);
  EXPECT_TRUE(r.interlock.decide(0.01).lamps_on);
  EXPECT_FALSE(UvInterlock().decide(0.0).lamps_on) << "no inputs: nothing permits";
}

TEST(UvInterlock, EachInputForcesTheLampsOffAtOnce) {
  const char* names[] = {"uv_lights request", "on rails",  "treatment speed", "people_detected",
                         "people_present",    "base stop", "lock safety/lock"};
  for (size_t input = 0; input < 7; ++input) {
    Rig r;
    r.allPermit(10.0);
    ASSERT_TRUE(r.interlock.decide(10.0).lamps_on);
    // The input turns at t = 10.02 s; the decision taken on that message (the node decides in its callback) is
    // off at the same instant: latency 0 on the simulated clock.
    r.interlock.update(input, false, 10.02, "why");
    const InterlockDecision d = r.interlock.decide(10.02);
    EXPECT_FALSE(d.lamps_on) << names[input];
    ASSERT_EQ(d.blocking.size(), 1u) << names[input];
    EXPECT_EQ(d.blocking[0], std::string(names[input]) + ": why");
    // Permitting again switches back on.
    r.interlock.update(input, true, 10.04);
    EXPECT_TRUE(r.interlock.decide(10.04).lamps_on) << names[input];
  }
}

TEST(UvInterlock, StaleInputsKeepTheLampsOff) {
  Rig r;
  r.allPermit(0.0);
  // Every stream refreshed every 20 ms except on rails, which stops at t = 0.
  double off_at = -1.0;
  const double check_period = 0.02;  // the node's check_rate of 50 Hz
  for (double t = check_period; t < 1.0; t += check_period) {
    for (size_t i = 0; i < r.interlock.size(); ++i) {
      if (i != r.rails) r.interlock.update(i, true, t);
    }
    if (!r.interlock.decide(t).lamps_on) {
      off_at = t;
      break;
    }
  }
  // Stale once older than 0.3 s: the first check after it, within one check period.
  EXPECT_GT(off_at, 0.3);
  EXPECT_LE(off_at, 0.3 + check_period + 1e-9);
  const auto d = r.interlock.decide(off_at);
  ASSERT_EQ(d.blocking.size(), 1u);
  EXPECT_EQ(d.blocking[0].rfind("on rails: stale (last 0.3", 0), 0u) << d.blocking[0];
}

TEST(UvInterlock, ZeroTimeoutNeverStales) {
  Rig r;
  r.allPermit(0.0);
  for (size_t i = 1; i < r.interlock.size(); ++i) r.interlock.update(i, true, 100.0);
  EXPECT_TRUE(r.interlock.decide(100.0).lamps_on) << "the latched request stays valid";
}

TEST(UvInterlock, RefusesANegativeTimeout) {
  UvInterlock interlock;
  EXPECT_THROW(interlock.add({"x", -0.1}), std::invalid_argument);
  EXPECT_THROW(interlock.update(3, true, 0.0), std::out_of_range);
}

TEST(UvInterlock, TreatmentSpeedWithinTolerance) {
  EXPECT_TRUE(atTreatmentSpeed(0.5, 0.5, 0.1));
  EXPECT_TRUE(atTreatmentSpeed(0.41, 0.5, 0.1));
  EXPECT_TRUE(atTreatmentSpeed(-0.55, 0.5, 0.1)) << "either direction along the rails";
  EXPECT_FALSE(atTreatmentSpeed(0.39, 0.5, 0.1));
  EXPECT_FALSE(atTreatmentSpeed(0.0, 0.5, 0.1)) << "standing still";
  EXPECT_FALSE(atTreatmentSpeed(0.61, 0.5, 0.1));
  EXPECT_FALSE(atTreatmentSpeed(std::nan(""), 0.5, 0.1));
}

TEST(SpeedWindow, OnFromTheInnerBandOffBelowTheOuter) {
  SpeedWindow w(0.5, 0.1, 0.05);
  EXPECT_FALSE(w.update(0.0));
  EXPECT_FALSE(w.update(0.42)) << "accelerating: not yet within the on tolerance";
  EXPECT_FALSE(w.update(0.449));
  EXPECT_TRUE(w.update(0.451));
  EXPECT_TRUE(w.update(0.5));
  EXPECT_TRUE(w.update(0.41)) << "slowing: kept until it leaves the outer tolerance";
  EXPECT_FALSE(w.update(0.39));
  EXPECT_FALSE(w.update(0.42)) << "back above 0.4 m/s is not enough to come on again";
  EXPECT_TRUE(w.update(-0.47)) << "either direction";
  EXPECT_FALSE(w.update(0.61));
  EXPECT_FALSE(w.update(0.58));
  EXPECT_TRUE(w.update(0.54));
  EXPECT_FALSE(w.update(std::nan("")));
  EXPECT_FALSE(w.update(0.41)) << "NaN resets the hold";
}

TEST(SpeedWindow, NoFlickerAtTheBandsEdge) {
  // The recorded relay flicker: the speed wavering round 0.4 m/s while braking switched the relay off/on/off.
  SpeedWindow w(0.5, 0.1, 0.05);
  int switches = 0;
  bool last = false;
  const double trace[] = {0.3, 0.38, 0.44, 0.46, 0.5, 0.5, 0.43, 0.399, 0.401, 0.398, 0.402, 0.35, 0.2};
  for (double v : trace) {
    const bool on = w.update(v);
    switches += on != last ? 1 : 0;
    last = on;
  }
  EXPECT_EQ(switches, 2) << "on once, off once";
  EXPECT_FALSE(last);
}

TEST(SpeedWindow, SafetyInputsStillSwitchOffAtOnce) {
  // The speed window's hold keeps only the speed input permitting; any other input blocks the lamps the same tick.
  Rig r;
  SpeedWindow w(0.5, 0.1, 0.05);
  r.allPermit(0.0);
  w.update(0.5);
  r.interlock.update(r.speed, w.update(0.41), 0.01);
  ASSERT_TRUE(r.interlock.decide(0.01).lamps_on);
  r.interlock.update(r.detected, false, 0.02, "a person is detected");
  EXPECT_FALSE(r.interlock.decide(0.02).lamps_on);
}

TEST(SpeedWindow, RefusesAnOnToleranceWiderThanTheBand) {
  EXPECT_THROW(SpeedWindow(0.5, 0.1, 0.2), std::invalid_argument);
  EXPECT_THROW(SpeedWindow(0.5, 0.1, -0.01), std::invalid_argument);
  EXPECT_NO_THROW(SpeedWindow(0.5, 0.1, 0.1));
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
