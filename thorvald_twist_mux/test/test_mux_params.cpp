#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "../src/ros/mux_params.h"

using thorvald_twist_mux::MuxEntry;
using thorvald_twist_mux::parseMuxEntries;
using XmlRpc::XmlRpcValue;

namespace {

XmlRpcValue entry(const std::string& name, const std::string& topic, XmlRpcValue timeout, XmlRpcValue priority) {
  XmlRpcValue e;
  if (!name.empty()) e["name"] = name;
  e["topic"] = topic;
  e["timeout"] = timeout;
  e["priority"] = priority;
  return e;
}

std::string errorOf(XmlRpcValue v) {
  try {
    parseMuxEntries(v, "topics", false);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(MuxParams, ListFormWithIntAndDoubleTimeouts) {
  XmlRpcValue list;
  list[0] = entry("navigation", "nav_vel", XmlRpcValue(1), XmlRpcValue(10));  // twist_mux dies on int timeouts
  list[1] = entry("joystick", "teleop_joy/cmd_vel", XmlRpcValue(0.5), XmlRpcValue(100));
  const auto entries = parseMuxEntries(list, "topics", false);
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_EQ(entries[0].name, "navigation");
  EXPECT_EQ(entries[0].topic, "nav_vel");
  EXPECT_DOUBLE_EQ(entries[0].timeout_s, 1.0);
  EXPECT_EQ(entries[0].priority, 10);
  EXPECT_FALSE(entries[0].stamped);
  EXPECT_DOUBLE_EQ(entries[1].timeout_s, 0.5);
  EXPECT_EQ(entries[1].priority, 100);
}

TEST(MuxParams, MapFormTakesNamesFromKeys) {
  XmlRpcValue map;
  map["nav"] = entry("", "nav_vel", XmlRpcValue(0.25), XmlRpcValue(10));
  map["nav"]["stamped"] = true;
  const auto entries = parseMuxEntries(map, "topics", false);
  ASSERT_EQ(entries.size(), 1u);
  EXPECT_EQ(entries[0].name, "nav");
  EXPECT_TRUE(entries[0].stamped);
}

TEST(MuxParams, StampedDefaultApplies) {
  XmlRpcValue list;
  list[0] = entry("a", "a", XmlRpcValue(0.0), XmlRpcValue(1));
  EXPECT_TRUE(parseMuxEntries(list, "topics", true)[0].stamped);
}

TEST(MuxParams, ErrorsNameEntryAndKey) {
  XmlRpcValue no_topic;
  no_topic[0]["name"] = "nav";
  no_topic[0]["timeout"] = 0.5;
  no_topic[0]["priority"] = 10;
  EXPECT_EQ(errorOf(no_topic), "topics[0] (nav): missing key 'topic'");

  XmlRpcValue no_name;
  no_name[0]["topic"] = "x";
  EXPECT_EQ(errorOf(no_name), "topics[0]: missing key 'name'");

  XmlRpcValue string_timeout;
  string_timeout[0] = entry("a", "a", XmlRpcValue("soon"), XmlRpcValue(1));
  EXPECT_EQ(errorOf(string_timeout), "topics[0] (a): 'timeout' is a string, expected a number [s]");

  XmlRpcValue double_priority;
  double_priority[0] = entry("a", "a", XmlRpcValue(0.5), XmlRpcValue(1.5));
  EXPECT_EQ(errorOf(double_priority), "topics[0] (a): 'priority' is a double, expected an integer 0..255");

  XmlRpcValue not_a_list("nav_vel");
  EXPECT_NE(errorOf(not_a_list).find("topics is a string"), std::string::npos);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
