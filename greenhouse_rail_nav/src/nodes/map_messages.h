#pragma once

#include <string>

#include <geometry_msgs/Pose.h>
#include <geometry_msgs/PoseArray.h>
#include <nav_msgs/OccupancyGrid.h>
#include <visualization_msgs/MarkerArray.h>

#include "greenhouse_rail_nav/map_analyzer.h"
#include "thorvald_map/occupancy_grid.h"

namespace greenhouse_rail_nav {

/// Lines, rear wall, headland edge, side walls, rail frames, rails and targets for RViz.
visualization_msgs::MarkerArray analysisMarkers(const MapAnalysis& analysis, double rail_gauge_m,
                                                const std::string& frame_id, const ros::Time& stamp);

}  // namespace greenhouse_rail_nav
