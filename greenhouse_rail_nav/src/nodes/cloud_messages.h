#pragma once

#include <string>

#include <sensor_msgs/PointCloud2.h>

#include "greenhouse_rail_nav/depth_camera.h"

namespace greenhouse_rail_nav {

/// Copies the x, y, z of a PointCloud2 into an OrganisedCloud (through thorvald_base::OrganisedCloudView). Returns
/// false with the reason when the message is malformed (missing or non-float fields, data shorter than its header
/// says).
bool fromMessage(const sensor_msgs::PointCloud2& msg, OrganisedCloud* cloud, std::string* error);

/// The inverse, for tests and tools: an organised cloud in frame_id.
sensor_msgs::PointCloud2 toMessage(const OrganisedCloud& cloud, const std::string& frame_id, const ros::Time& stamp);

}  // namespace greenhouse_rail_nav
