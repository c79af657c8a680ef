#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <sensor_msgs/LaserScan.h>

#include "thorvald_base/pose2d.h"
#include "thorvald_map/ros/conversions.h"  // poses and grids: the one set of conversions

namespace thorvald_navigation {

/// Beam end points of a scan in base_link, given the sensor's pose in base_link (the scan plane assumed parallel
/// to the floor). Beams outside [range_min, min(range_max, max_range)] and non-finite ones go to `dropped`
/// count; beams reading "nothing" (inf or >= range_max) are returned in `free_ends` at `max_range` when given.
struct ScanPoints {
  std::vector<Eigen::Vector2d> hits;
  std::vector<Eigen::Vector2d> free_ends;
  int dropped = 0;
};
/// Returns an empty string or what is wrong with the scan message itself (angles, sizes).
std::string scanToPoints(const sensor_msgs::LaserScan& scan, const thorvald_base::Pose2D& sensor_in_base,
                         double max_range, ScanPoints* out);

}  // namespace thorvald_navigation
