// A small machine that shows the status topic: COUNT runs `cycles` times (each waits `step_s` of ROS
// time), then REPORT finishes the machine. cycles = -1 counts forever until preempted through
// ~preempt (std_msgs/Empty). The node exits when the machine finishes.
#include <thread>

#include <ros/ros.h>
#include <std_msgs/Empty.h>
#include <thorvald_common/ros/param_reader.h>

#include "thorvald_state_machine/ros/status_publisher.h"
#include "thorvald_state_machine/state_machine.h"

namespace tsm = thorvald_state_machine;

int main(int argc, char** argv) {
  ros::init(argc, argv, "state_machine_demo");
  ros::NodeHandle pnh("~");
  int cycles = 3;
  double step_s = 0.1;
  try {
    thorvald_common::ParamReader params(pnh);
    cycles = params.integer("cycles", cycles, -1);
    step_s = params.number("step_s", step_s, thorvald_common::ParamRange::aboveUpTo(0.0, 3600.0), "s");
    params.finish();
  } catch (const thorvald_common::ParamError& e) {
    ROS_FATAL_STREAM(e.what());
    return 1;
  }

  tsm::StateMachine machine("demo", {"done"});
  machine.add("COUNT",
              std::make_unique<tsm::FunctionState>(std::vector<std::string>{"again", "enough", tsm::kPreempted},
                                                   [cycles, step_s](tsm::UserData& ud, tsm::ExecutionContext& ctx) {
                                                     const ros::Time until = ros::Time::now() + ros::Duration(step_s);
                                                     while (ros::ok() && ros::Time::now() < until) {
                                                       if (ctx.preemptRequested()) return tsm::kPreempted;
                                                       std::this_thread::sleep_for(std::chrono::milliseconds(5));
                                                     }
                                                     const int n = ud.getOr<int>("count", 0) + 1;
                                                     ud.set<int>("count", n);
                                                     return (cycles >= 0 && n >= cycles) ? std::string("enough")
                                                                                         : std::string("again");
                                                   }),
              {{"again", "COUNT"}, {"enough", "REPORT"}});
  machine.add("REPORT",
              std::make_unique<tsm::FunctionState>(std::vector<std::string>{"ok"},
                                                   [](tsm::UserData& ud, tsm::ExecutionContext&) {
                                                     ROS_INFO("demo counted %d cycles", ud.get<int>("count"));
                                                     return std::string("ok");
                                                   }),
              {{"ok", "done"}});

  tsm::StatusPublisher status(pnh, machine, "machine_status", 0.5);
  ros::Subscriber preempt = pnh.subscribe<std_msgs::Empty>(
      "preempt", 1, [&machine](const std_msgs::Empty::ConstPtr&) { machine.requestPreempt(); });
  ros::AsyncSpinner spinner(1);
  spinner.start();

  tsm::UserData userdata;
  const std::string outcome = machine.run(userdata);
  ROS_INFO("demo machine finished: %s", outcome.c_str());
  status.publishNow();
  // Stay up so late subscribers see the final (latched) status.
  ros::waitForShutdown();
  return 0;
}
