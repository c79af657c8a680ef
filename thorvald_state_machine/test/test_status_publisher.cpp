#include <gtest/gtest.h>

#include <mutex>

#include <ros/ros.h>
#include <thorvald_common/ros/wait_for.h>
#include <std_msgs/Empty.h>

#include "thorvald_state_machine/MachineStatus.h"
#include "thorvald_state_machine/ros/status_publisher.h"

namespace tsm = thorvald_state_machine;

namespace {

/// Keeps the last status of one topic.
struct StatusListener {
  explicit StatusListener(const std::string& topic) {
    ros::NodeHandle nh;
    sub = nh.subscribe<tsm::MachineStatus>(topic, 50, [this](const tsm::MachineStatus::ConstPtr& msg) {
      std::lock_guard<std::mutex> lock(mutex);
      last = *msg;
      ++count;
      if (msg->running && !msg->active_state.empty()) seen_running_in = msg->active_state;
    });
  }
  template <typename Predicate>
  bool waitFor(Predicate predicate, double timeout_s) {
    return thorvald_common::waitFor(
        [&] {
          std::lock_guard<std::mutex> lock(mutex);
          return count > 0 && predicate(last);
        },
        timeout_s, thorvald_common::sleepEvery(0.01));
  }
  ros::Subscriber sub;
  std::mutex mutex;
  tsm::MachineStatus last;
  std::string seen_running_in;
  int count = 0;
};

}  // namespace

TEST(StatusPublisher, ConvertsSnapshots) {
  tsm::StatusSnapshot snapshot;
  snapshot.machine = "m";
  snapshot.active_state = "A/B";
  snapshot.last_outcome = "x";
  snapshot.running = true;
  snapshot.transitions = 7;
  snapshot.history.push_back(tsm::TransitionRecord{12.5, "A", "x", "B"});
  const auto msg = tsm::toMsg(snapshot, ros::Time(3.0));
  EXPECT_EQ(msg.header.stamp, ros::Time(3.0));
  EXPECT_EQ(msg.machine, "m");
  EXPECT_EQ(msg.active_state, "A/B");
  EXPECT_TRUE(msg.running);
  EXPECT_EQ(msg.transitions, 7u);
  ASSERT_EQ(msg.history.size(), 1u);
  EXPECT_DOUBLE_EQ(msg.history[0].stamp.toSec(), 12.5);
  EXPECT_EQ(msg.history[0].next, "B");
}

TEST(StatusPublisher, ReportsAFinishedMachine) {
  StatusListener listener("/counting/machine_status");
  ASSERT_TRUE(
      listener.waitFor([](const tsm::MachineStatus& s) { return !s.running && s.last_outcome == "done"; }, 30.0));
  std::lock_guard<std::mutex> lock(listener.mutex);
  EXPECT_EQ(listener.last.machine, "demo");
  EXPECT_EQ(listener.last.transitions, 4u);  // COUNT x3 + REPORT
  ASSERT_EQ(listener.last.history.size(), 4u);
  EXPECT_EQ(listener.last.history[2].outcome, "enough");
  EXPECT_EQ(listener.last.history[3].next, "-> done");
}

TEST(StatusPublisher, PreemptionThroughTheTopic) {
  StatusListener listener("/forever/machine_status");
  ASSERT_TRUE(listener.waitFor(
      [](const tsm::MachineStatus& s) { return s.running && s.active_state == "COUNT" && s.transitions >= 2; }, 30.0));
  ros::NodeHandle nh;
  ros::Publisher preempt = nh.advertise<std_msgs::Empty>("/forever/preempt", 1, true);
  preempt.publish(std_msgs::Empty());
  ASSERT_TRUE(listener.waitFor([](const tsm::MachineStatus& s) { return !s.running; }, 30.0));
  std::lock_guard<std::mutex> lock(listener.mutex);
  EXPECT_EQ(listener.last.last_outcome, "preempted");
  EXPECT_FALSE(listener.last.preempt_requested);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_status_publisher");
  ros::AsyncSpinner spinner(1);
  spinner.start();
  return RUN_ALL_TESTS();
}
