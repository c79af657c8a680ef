#pragma once

#include <string>

#include <opencv2/core.hpp>
#include <sensor_msgs/PointCloud2.h>
#include <visualization_msgs/MarkerArray.h>

#include "cotton_harvester/BollArray.h"
#include "cotton_harvester/perception/perception_pipeline.h"

namespace cotton_harvester {

/// Copies an organised PointCloud2 with float32 x, y, z fields into a CV_32FC3 matrix (rows = height).
/// Returns false with a reason for an unorganised cloud, missing or non-float fields or a short data buffer.
bool cloudToMat(const sensor_msgs::PointCloud2& cloud, cv::Mat* points, std::string* error);

/// The message of a frame's bolls.
BollArray toBollArray(const perception::FrameResult& result, const std_msgs::Header& header);

/// Spheres at the bolls (green when reachable, grey otherwise, blue for the nearest) and a cube at the
/// end-effector; the previous frame's markers are deleted first.
visualization_msgs::MarkerArray toMarkers(const perception::FrameResult& result, const std_msgs::Header& header);

}  // namespace cotton_harvester
