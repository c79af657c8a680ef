// thorvald_sim: MuJoCo world with Thorvald robots, sensors and /clock. See README.md.
#include <ros/ros.h>

#include "sim_ros.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "thorvald_sim");
  thorvald_sim::SimRos sim(ros::NodeHandle(), ros::NodeHandle("~"));
  if (!sim.start()) return 1;
  sim.run();
  return 0;
}
