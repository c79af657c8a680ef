// The gpsd client's connection decisions: retries while gpsd is missing, "gpsd lost" after the timeout, the
// diagnostics' level and message in each state.
#include <gtest/gtest.h>

#include <stdexcept>

#include "thorvald_gnss/gpsd_link.h"

namespace thorvald_gnss {
namespace {

TEST(GpsdLink, RetriesEveryIntervalWhileGpsdIsMissing) {
  GpsdLink link{GpsdLinkParams{2.0, 1.0}};
  EXPECT_TRUE(link.shouldConnect(100.0));
  link.connectFailed(100.0, "gpsd at localhost:2947: connection refused");
  EXPECT_FALSE(link.shouldConnect(100.5));
  EXPECT_TRUE(link.shouldConnect(101.0));
  const LinkHealth h = link.health(101.0);
  EXPECT_EQ(h.level, LinkLevel::kError);
  EXPECT_EQ(h.message, "gpsd lost: gpsd at localhost:2947: connection refused; retrying every 1.0 s");
  EXPECT_EQ(link.failedAttempts(), 1u);
}

TEST(GpsdLink, HealthyWithFixesThenNoFixThenLost) {
  GpsdLink link{GpsdLinkParams{2.0, 1.0}};
  link.connected(0.0);
  EXPECT_FALSE(link.shouldConnect(0.1));
  EXPECT_EQ(link.health(0.5).level, LinkLevel::kError);  // connected, nothing yet
  link.report(0.6, true, "RTK fixed");
  EXPECT_EQ(link.health(0.7).level, LinkLevel::kOk);
  EXPECT_EQ(link.health(0.7).message, "RTK fixed");
  link.report(1.0, false, "no fix");
  link.report(3.0, false, "no fix");
  EXPECT_EQ(link.health(3.1).level, LinkLevel::kWarn);  // reports come, none with a fix for 2.5 s
  EXPECT_EQ(link.health(3.1).message, "no fix for 2.5 s (gpsd reports no position)");
  EXPECT_FALSE(link.timedOut(4.9));
  EXPECT_TRUE(link.timedOut(5.1));
  EXPECT_EQ(link.health(5.1).level, LinkLevel::kError);
  link.disconnected(5.1, "no report from gpsd for 2 s");
  EXPECT_FALSE(link.isConnected());
  EXPECT_FALSE(link.shouldConnect(5.5));
  EXPECT_TRUE(link.shouldConnect(6.1));
  link.connected(6.1);
  EXPECT_EQ(link.connections(), 2u);
  EXPECT_EQ(link.fixes(), 1u);
  EXPECT_EQ(link.reports(), 3u);
}

TEST(GpsdLink, TimesOutWhenNothingComesAfterConnecting) {
  GpsdLink link{GpsdLinkParams{2.0, 1.0}};
  link.connected(10.0);
  EXPECT_FALSE(link.timedOut(11.9));
  EXPECT_TRUE(link.timedOut(12.1));
  EXPECT_FALSE(GpsdLink(GpsdLinkParams{}).timedOut(100.0)) << "not connected: nothing to time out";
}

TEST(GpsdLink, RejectsBadParameters) {
  EXPECT_EQ((GpsdLinkParams{0.0, -1.0}).validate().size(), 2u);
  EXPECT_THROW(GpsdLink(GpsdLinkParams{0.0, 1.0}), std::invalid_argument);
}

}  // namespace
}  // namespace thorvald_gnss
