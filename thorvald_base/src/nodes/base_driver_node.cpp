#include <ros/ros.h>

#include <csignal>
#include <iostream>

#include "base_driver_ros.h"

namespace {
// SIGTERM ends the node as SIGINT does: the bus is closed (a virtual bus endpoint removes its socket file).
void onTerminate(int) { ros::requestShutdown(); }
}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "base_driver");
  std::signal(SIGTERM, onTerminate);
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  std::unique_ptr<thorvald_base::BaseDriverRos> node;
  try {
    node = std::make_unique<thorvald_base::BaseDriverRos>(nh, pnh);
  } catch (const std::exception& e) {
    // Stopped (SIGINT, SIGTERM) while starting: rosconsole is shut down by then, so the reason goes to stderr.
    if (!ros::ok() || ros::isShuttingDown())
      std::cerr << "base_driver stopped while starting: " << e.what() << std::endl;
    ROS_FATAL_STREAM("base_driver cannot start: " << e.what());
    return 1;
  }
  ros::spin();
  return 0;
}
