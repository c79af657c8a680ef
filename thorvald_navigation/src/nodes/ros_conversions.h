#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <geometry_msgs/Pose.h>
#include <geometry_msgs/Transform.h>
#include <nav_msgs/OccupancyGrid.h>
#include <sensor_msgs/LaserScan.h>

#include "thorvald_navigation/grid2d.h"
#include "thorvald_navigation/pose2d.h"

namespace thorvald_navigation {

Pose2D fromPose(const geometry_msgs::Pose& p);
Pose2D fromTransform(const geometry_msgs::Transform& t);
geometry_msgs::Pose toPose(const Pose2D& p);
geometry_msgs::Transform toTransform(const Pose2D& p);

/// Converts a grid message; returns an empty string or what is wrong with it (size, resolution, rotation).
std::string fromGridMessage(const nav_msgs::OccupancyGrid& msg, Grid2D* grid);
nav_msgs::OccupancyGrid toGridMessage(const Grid2D& grid, const std::string& frame_id);

/// Beam end points of a scan in base_link, given the sensor's pose in base_link (the scan plane assumed parallel
/// to the floor). Beams outside [range_min, min(range_max, max_range)] and non-finite ones go to `dropped`
/// count; beams reading "nothing" (inf or >= range_max) are returned in `free_ends` at `max_range` when given.
struct ScanPoints {
  std::vector<Eigen::Vector2d> hits;
  std::vector<Eigen::Vector2d> free_ends;
  int dropped = 0;
};
/// Returns an empty string or what is wrong with the scan message itself (angles, sizes).
std::string scanToPoints(const sensor_msgs::LaserScan& scan, const Pose2D& sensor_in_base, double max_range,
                         ScanPoints* out);

}  // namespace thorvald_navigation
