// The harvest run's time by state: entries, time in each state, the state still active at the end.
#include <gtest/gtest.h>

#include "cotton_harvester_sim/harvest_run.h"

using cotton_harvester::sim::HarvestRunReport;
using cotton_harvester::sim::StateTimeTally;

TEST(StateTimeTally, TimeAndEntriesPerState) {
  HarvestRunReport report;
  StateTimeTally tally(&report);
  tally.observe("", 0.0);  // not started yet: nothing counted
  tally.observe("OBSERVE", 1.0);
  tally.observe("OBSERVE", 1.5);  // the same state again: neither an entry nor a split
  tally.observe("PICK", 3.0);
  tally.observe("OBSERVE", 7.0);
  tally.finish(7.25);
  EXPECT_EQ(report.states_visited, (std::set<std::string>{"OBSERVE", "PICK"}));
  EXPECT_EQ(report.state_entries.at("OBSERVE"), 2);
  EXPECT_EQ(report.state_entries.at("PICK"), 1);
  EXPECT_DOUBLE_EQ(report.state_time_s.at("OBSERVE"), 2.0 + 0.25);
  EXPECT_DOUBLE_EQ(report.state_time_s.at("PICK"), 4.0);
}

TEST(StateTimeTally, EndedMachineStopsTheClock) {
  HarvestRunReport report;
  StateTimeTally tally(&report);
  tally.observe("MOVE_FORWARD", 2.0);
  tally.observe("", 5.0);  // the machine ended: no active state
  tally.finish(9.0);
  EXPECT_DOUBLE_EQ(report.state_time_s.at("MOVE_FORWARD"), 3.0);
  EXPECT_EQ(report.state_time_s.size(), 1u);
  EXPECT_EQ(report.state_entries.count(""), 0u);
  EXPECT_EQ(report.states_visited.count(""), 0u);
}

TEST(StateTimeTally, NothingObservedNothingCounted) {
  HarvestRunReport report;
  StateTimeTally tally(&report);
  tally.finish(3.0);
  EXPECT_TRUE(report.state_time_s.empty());
  EXPECT_TRUE(report.state_entries.empty());
  EXPECT_TRUE(report.states_visited.empty());
}
