// The UV mission's people and obstacle detection on ROS: every lidar scan is evaluated against the protected zone
// (obstacle_zones.h) for the mission's current context, with the headland map (points of the map, outside it, or in
// the map analyzer's keep-out zone beyond the headland edge are known: not headland) and the rear range finders; the
// verdict goes to the mission, to the UV interlock (people_detected) and to RViz (obstacles markers). Also watches the
// lamps' relay boards (io/<board>/state_unknown).
#pragma once

#include <nav_msgs/OccupancyGrid.h>
#include <ros/ros.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/Range.h>
#include <std_msgs/Bool.h>
#include <tf2_ros/buffer.h>
#include <thorvald_common/ros/param_reader.h>

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "greenhouse_rail_nav/obstacle_zones.h"
#include "thorvald_map/occupancy_grid.h"

namespace greenhouse_rail_nav {

class ZoneWatch {
 public:
  struct Config {
    ZoneParams zone;
    std::string map_frame = "map", base_frame = "base_link";
    std::vector<std::string> rear_sensors{"rear_left", "rear_right", "rear_centre", "rear_left_corner",
                                          "rear_right_corner"};  ///< topics ultrasonic/<name>
    std::vector<std::string> relay_boards;                       ///< topics io/<board>/state_unknown
    double rear_timeout_s = 0.5;                                 ///< an older rear reading is not used [s]
    double scan_timeout_s = 0.5;  ///< no scan evaluated for this long: the zone counts as blocked [s]
  };
  /// Reads the zone's parameters (zone/...) and the rear sensors' and relay boards' lists.
  static void readParams(thorvald_common::ParamReader& params, Config* c);

  ZoneWatch(ros::NodeHandle& nh, const Config& c, tf2_ros::Buffer& tf);
  void setContext(const ZoneContext& ctx);
  /// The latest scan's verdict; blocked when no scan was evaluated within scan_timeout_s (no lidar, or no
  /// transform from its frame to base_link).
  ZoneVerdict verdict();
  bool lightsInDoubt(std::string* why);

 private:
  void onScan(const sensor_msgs::LaserScan& m);
  void onMap(const nav_msgs::OccupancyGrid& m);
  void onKeepOut(const nav_msgs::OccupancyGrid& m);
  /// Converts a grid message into `out` under the mutex; false (and a warning naming `what`) when it is unusable.
  bool storeGrid(const nav_msgs::OccupancyGrid& m, const char* what, thorvald_map::OccupancyGrid* out);
  void onRear(size_t i, const sensor_msgs::Range& m);
  void onRelay(size_t i, const std_msgs::Bool& m);
  /// The scan's returns in base_link; false without the lidar's transform.
  bool toBase(const sensor_msgs::LaserScan& m, std::vector<ScanPoint>* pts, double* lidar_x);
  KnownPoint knownInMap();
  void publishMarkers(const ZoneVerdict& v, const ZoneContext& ctx, const ros::Time& stamp);

  Config cfg_;
  tf2_ros::Buffer& tf_;
  std::mutex mutex_;
  ZoneContext ctx_;
  ZoneVerdict verdict_;
  std::unique_ptr<PersonConfirmation> confirm_;  // people over consecutive scans
  ros::Time evaluated_;                          // when verdict_ was taken
  thorvald_map::OccupancyGrid map_;
  bool have_map_ = false;
  thorvald_map::OccupancyGrid
      keep_out_;  // the rows beyond the headland edge (map_analyzer's keep_out_map; empty: none)
  std::vector<double> rear_range_;
  std::vector<ros::Time> rear_stamp_;
  std::vector<int> relay_unknown_;  // -1 not heard, 0 confirmed, 1 in doubt
  ros::Time last_markers_;
  std::vector<ros::Subscriber> subs_;
  ros::Publisher people_pub_, markers_pub_;
};

}  // namespace greenhouse_rail_nav
