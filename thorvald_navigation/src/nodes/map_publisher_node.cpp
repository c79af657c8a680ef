// map_publisher: publishes a map_server YAML + PGM map on `map` (latched) and `map_metadata`, and answers
// `static_map` (nav_msgs/GetMap), like map_server's map_server node.
#include <string>

#include <nav_msgs/GetMap.h>
#include <nav_msgs/MapMetaData.h>
#include <nav_msgs/OccupancyGrid.h>
#include <ros/ros.h>
#include <thorvald_common/ros/param_reader.h>

#include "ros_conversions.h"
#include "thorvald_map/map_file.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "map_publisher");
  ros::NodeHandle nh, pnh("~");
  std::string map_file, frame_id = "map";
  try {
    thorvald_common::ParamReader r(pnh, "map_publisher");
    map_file = r.text("map_file", map_file);
    frame_id = r.text("frame_id", frame_id);
    r.finish();
    if (map_file.empty()) throw thorvald_common::ParamError("map_publisher: ~map_file (map_server YAML) must be set");
    if (frame_id.empty()) throw thorvald_common::ParamError("map_publisher: ~frame_id must not be empty");
  } catch (const thorvald_common::ParamError& e) {
    ROS_FATAL_STREAM(e.what());
    return 1;
  }
  thorvald_map::OccupancyGrid grid;
  std::string error;
  if (!thorvald_map::loadMap(map_file, &grid, &error)) {
    ROS_FATAL_STREAM("map_publisher: " << error);
    return 1;
  }
  nav_msgs::OccupancyGrid map = thorvald_map::toGridMessage(grid, frame_id);
  map.header.stamp = ros::Time::now();
  map.info.map_load_time = map.header.stamp;
  ros::Publisher map_pub = nh.advertise<nav_msgs::OccupancyGrid>("map", 1, true);
  ros::Publisher meta_pub = nh.advertise<nav_msgs::MapMetaData>("map_metadata", 1, true);
  map_pub.publish(map);
  meta_pub.publish(map.info);
  ros::ServiceServer srv = nh.advertiseService<nav_msgs::GetMap::Request, nav_msgs::GetMap::Response>(
      "static_map", [&map](nav_msgs::GetMap::Request&, nav_msgs::GetMap::Response& res) {
        res.map = map;
        return true;
      });
  ROS_INFO("map_publisher: %s, %d x %d cells of %.3f m", map_file.c_str(), grid.width, grid.height, grid.resolution_m);
  ros::spin();
  return 0;
}
