#include <ros/ros.h>

#include "base_driver_ros.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "base_driver");
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  std::unique_ptr<thorvald_base::BaseDriverRos> node;
  try {
    node = std::make_unique<thorvald_base::BaseDriverRos>(nh, pnh);
  } catch (const std::exception& e) {
    ROS_FATAL_STREAM("base_driver cannot start: " << e.what());
    return 1;
  }
  ros::spin();
  return 0;
}
