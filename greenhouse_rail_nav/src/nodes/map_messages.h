#pragma once

#include <string>

#include <geometry_msgs/Pose.h>
#include <geometry_msgs/PoseArray.h>
#include <nav_msgs/OccupancyGrid.h>
#include <visualization_msgs/MarkerArray.h>

#include "greenhouse_rail_nav/map_analyzer.h"
#include "greenhouse_rail_nav/occupancy_map.h"

namespace greenhouse_rail_nav {

/// Conversions between the map analyzer's plain types and ROS messages.
OccupancyMap fromMessage(const nav_msgs::OccupancyGrid& grid);
nav_msgs::OccupancyGrid toMessage(const OccupancyMap& map, const std::string& frame_id, const ros::Time& stamp);
geometry_msgs::Pose toPoseMessage(const Pose2D& pose);
/// Yaw of a quaternion that rotates about z only [rad].
double yawOf(const geometry_msgs::Quaternion& q);
/// Lines, rear wall, headland edge, side walls, rail frames, rails and targets for RViz.
visualization_msgs::MarkerArray analysisMarkers(const MapAnalysis& analysis, double rail_gauge_m,
                                                const std::string& frame_id, const ros::Time& stamp);

}  // namespace greenhouse_rail_nav
