#pragma once

// headland_navigator's parameters: read and checked in one place (the node's thin shell calls loadSettings once).
#include <string>
#include <vector>

#include <ros/node_handle.h>

#include "thorvald_navigation/costmap.h"
#include "thorvald_navigation/goal_runner.h"
#include "thorvald_navigation/grid_planner.h"

namespace thorvald_navigation {

struct Settings {
  std::string global_frame = "map", base_frame = "base_link";
  std::string keep_out_topic = "keep_out_map";
  std::string localization_status_topic = "map_localizer/status";  // empty: no status read (amcl)
  double controller_frequency = 20.0;
  double footprint_padding = 0.05;
  std::vector<double> footprint;       // flat x0 y0 x1 y1 ...; empty: robot_description, else the robot file
  std::string drive_mode = "auto";     // auto | omnidirectional | differential
  double obstacle_range = 3.0;         // lidar points farther than this are not obstacles [m]
  double obstacle_check_ahead = 1.5;   // path length checked for obstacles [m]
  double final_approach = 0.3;         // differential: the last metres driven straight along the goal heading [m]
  double obstacle_update_rate = 10.0;  // lidar obstacles enter the costmap (and its inflation) at most this often [Hz]
  double scan_max_age = 0.5;           // obstacles older than this are forgotten [s]
  CostmapParams costmap;
  PlannerParams planner;
  GoalRunnerParams goal;  // the goal lifecycle: path follower, localisation gate, waits, settling, corrections
};

/// The footprint polygon from a flat list x0 y0 x1 y1 ..., padded outwards by `padding` [m].
Footprint makeFootprint(const std::vector<double>& flat, double padding);

/// Reads and checks the node's parameters (and the robot file when `~footprint` is not set); false with the reason
/// in `error` when one is wrong.
bool loadSettings(const ros::NodeHandle& nh, const ros::NodeHandle& pnh, Settings* s, std::string* error);

}  // namespace thorvald_navigation
