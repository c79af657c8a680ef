// Node `twist_mux`: selects which velocity command reaches the base (see README.md).
#include <exception>

#include <ros/ros.h>

#include "mux_node.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "twist_mux");
  // Handles outlive the try block: destroying the last one shuts ROS (and its logging) down.
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  try {
    thorvald_twist_mux::MuxNode node(nh, pnh);
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("twist_mux cannot start: %s", e.what());
    return 1;
  }
  return 0;
}
