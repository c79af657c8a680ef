#pragma once

// The one organised-cloud message builder of the package's ROS tests (perception node tests, fake rover topics).

#include <cstdint>
#include <cstring>

#include <opencv2/core.hpp>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Header.h>

namespace cotton_harvester {
namespace test {

/// An organised PointCloud2 (float32 x, y, z) from a CV_32FC3 matrix.
inline sensor_msgs::PointCloud2 toCloud(const cv::Mat& points, const std_msgs::Header& header) {
  sensor_msgs::PointCloud2 cloud;
  cloud.header = header;
  cloud.height = static_cast<uint32_t>(points.rows);
  cloud.width = static_cast<uint32_t>(points.cols);
  const char* names[3] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i) {
    sensor_msgs::PointField field;
    field.name = names[i];
    field.offset = 4 * i;
    field.datatype = sensor_msgs::PointField::FLOAT32;
    field.count = 1;
    cloud.fields.push_back(field);
  }
  cloud.point_step = 12;
  cloud.row_step = 12 * cloud.width;
  cloud.is_dense = false;
  cloud.data.resize(static_cast<size_t>(cloud.row_step) * cloud.height);
  for (int v = 0; v < points.rows; ++v)
    std::memcpy(cloud.data.data() + static_cast<size_t>(v) * cloud.row_step, points.ptr(v), cloud.row_step);
  return cloud;
}

}  // namespace test
}  // namespace cotton_harvester
