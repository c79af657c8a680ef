// Node `twist_mux`: selects which velocity command reaches the base (see README.md).
#include <exception>

#include <ros/ros.h>
#include <thorvald_teleop/stop_signals.h>

#include "mux_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "twist_mux", ros::init_options::NoSigintHandler);
  // SIGINT and SIGTERM stop the node in order, within a second in every state; destroyed last.
  thorvald_teleop::StopSignals stop_signals(ros::requestShutdown, 0.7);
  // Handles outlive the try block: destroying the last one shuts ROS (and its logging) down.
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  if (!ros::ok()) return 0;  // stopped while waiting for the master
  try {
    thorvald_base::ParamReader params(pnh);
    thorvald_twist_mux::MuxNode node(nh, pnh, params);
    params.finish();  // warns about unread (misspelt) parameters, logs the effective values
    ros::spin();
  } catch (const std::exception& e) {
    // Stopped during start-up (the parameters could not be read): roscpp's isShuttingDown() is false again once
    // its shutdown has finished, so the signal itself is what tells.
    if (thorvald_teleop::StopSignals::requested() || !ros::ok()) return 0;
    ROS_FATAL("twist_mux cannot start: %s", e.what());
    return 1;
  }
  return 0;
}
