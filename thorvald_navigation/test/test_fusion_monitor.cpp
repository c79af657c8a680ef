// FusionMonitor: a fusion's health from its inputs' arrivals, fixes and refusals.
#include <gtest/gtest.h>

#include "thorvald_navigation/fusion_monitor.h"

namespace tn = thorvald_navigation;

TEST(FusionMonitor, FreshInputsAreOk) {
  tn::FusionMonitor m;
  m.addInput("odom0", 0.5, true);
  m.addInput("odom1 (odometry/gps)", 2.0, true);
  EXPECT_TRUE(m.evaluate(0.1).localization_ok);  // within the first timeout: still starting
  m.received("odom0", 1.0);
  m.received("odom1 (odometry/gps)", 1.0);
  const tn::FusionHealth h = m.evaluate(1.2);
  EXPECT_EQ(h.level, tn::FusionHealth::kOk);
  EXPECT_TRUE(h.localization_ok);
  EXPECT_EQ(h.summary(), "fusing");
}

TEST(FusionMonitor, NeverReceivedIsAnError) {
  tn::FusionMonitor m;
  m.addInput("gps/fix", 2.0, true);
  const tn::FusionHealth h = m.evaluate(2.5);
  EXPECT_EQ(h.level, tn::FusionHealth::kError);
  EXPECT_FALSE(h.localization_ok);
  EXPECT_EQ(h.summary(), "gps/fix: nothing received since start");
}

TEST(FusionMonitor, StaleNoFixAndRefusedInputs) {
  tn::FusionMonitor m;
  m.addInput("gps/fix", 2.0, true);
  m.received("gps/fix", 10.0);
  EXPECT_TRUE(m.evaluate(11.9).localization_ok);
  tn::FusionHealth h = m.evaluate(12.5);
  EXPECT_FALSE(h.localization_ok);
  EXPECT_NE(h.summary().find("nothing for 2.5 s (timeout 2 s)"), std::string::npos) << h.summary();
  m.received("gps/fix", 13.0, false, "the receiver reports no fix");
  h = m.evaluate(13.1);
  EXPECT_EQ(h.summary(), "gps/fix: the receiver reports no fix");
  m.received("gps/fix", 14.0);
  m.refused("gps/fix", "pose: Mahalanobis distance 40 sigma >= gate 5");
  h = m.evaluate(14.1);
  EXPECT_FALSE(h.localization_ok);
  EXPECT_NE(h.summary().find("refused (pose: Mahalanobis"), std::string::npos) << h.summary();
  m.fused("gps/fix");
  EXPECT_TRUE(m.evaluate(14.2).localization_ok);
}

TEST(FusionMonitor, OptionalInputOnlyWarns) {
  tn::FusionMonitor m;
  m.addInput("imu1", 0.5, false);
  const tn::FusionHealth h = m.evaluate(1.0);
  EXPECT_EQ(h.level, tn::FusionHealth::kWarn);
  EXPECT_TRUE(h.localization_ok);
}
