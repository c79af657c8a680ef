#pragma once

#include <string>

#include <geometry_msgs/Pose.h>
#include <geometry_msgs/Quaternion.h>
#include <geometry_msgs/Transform.h>
#include <nav_msgs/OccupancyGrid.h>
#include <ros/time.h>

#include "thorvald_base/pose2d.h"
#include "thorvald_map/occupancy_grid.h"

namespace thorvald_map {

/// The ROS side of the planar types: thorvald_base::Pose2D <-> geometry_msgs, OccupancyGrid <-> nav_msgs. Nodes of
/// every package convert here, so that a pose or a grid means the same on every topic.

/// Heading of a quaternion about z [rad] (normalised first; NaN for a zero or non-finite quaternion).
double yawOf(const geometry_msgs::Quaternion& q);
/// A pose's x, y and heading; the heading is NaN for an unusable quaternion (see Pose2D::finite()).
thorvald_base::Pose2D fromPose(const geometry_msgs::Pose& p);
thorvald_base::Pose2D fromTransform(const geometry_msgs::Transform& t);
geometry_msgs::Pose toPose(const thorvald_base::Pose2D& p);
geometry_msgs::Transform toTransform(const thorvald_base::Pose2D& p);

/// Converts a grid message. Returns false with what is wrong (size, resolution, origin). `unrotated`: an origin turned
/// by more than 1e-6 rad is refused and a smaller turn (quaternion round-off) is taken as none, for code that works
/// on unrotated grids. The message carries no wall surface: grid->surface is left empty.
bool fromGridMessage(const nav_msgs::OccupancyGrid& msg, OccupancyGrid* grid, std::string* error,
                     bool unrotated = false);
/// The grid as a message in `frame_id`, stamped (and map_load_time) `stamp`.
nav_msgs::OccupancyGrid toGridMessage(const OccupancyGrid& grid, const std::string& frame_id,
                                      const ros::Time& stamp = ros::Time());

}  // namespace thorvald_map
