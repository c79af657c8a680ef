// The uv_mission node's parameters: the mission's (UvMissionParams), the robot interface's and how the node runs it.
#pragma once

#include <thorvald_common/ros/param_reader.h>

#include <string>

#include "greenhouse_rail_nav/uv_mission.h"
#include "zone_watch.h"

namespace greenhouse_rail_nav {

/// The robot interface's settings (RosMissionIO).
struct MissionIoConfig {
  std::string map_frame = "map", base_frame = "base_link";
  double rate_hz = 50.0, odom_timeout_s = 0.5, scan_half_width_rad = 0.05;
  /// Switch rail_detector on (rail_detector/enable) only while the mission waits for a detection: between them the
  /// detector, and a depth camera that publishes only to subscribers, stay idle.
  bool pause_rail_detection = true;
  ZoneWatch::Config zones;
};

/// The node's parameters: the mission's, the robot interface's and how the node runs it.
struct NodeSettings {
  UvMissionParams mission;
  MissionIoConfig io;
  std::string rail_sets_file, progress_file;
  bool autostart = true, exit_when_done = false;
  double wait_for_rail_sets_s = 0.0;  ///< [s]
  /// Every rail set's length from its rail start when the rail-set file gives none [m]; 0: unknown.
  double rail_length_m = 0.0;
};

/// Every private parameter, checked; throws ParamError naming the bad one.
NodeSettings readSettings(ros::NodeHandle& pnh);

}  // namespace greenhouse_rail_nav
