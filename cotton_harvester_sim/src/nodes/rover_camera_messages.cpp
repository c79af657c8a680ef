#include "rover_camera_messages.h"

#include <cstring>

namespace cotton_harvester {
namespace sim {

CameraMessages cameraMessages(const cv::Mat& bgr, const cv::Mat& cloud, const RoverSimParams& p,
                              const std_msgs::Header& header) {
  CameraMessages m;
  sensor_msgs::Image& image = m.image;
  image.header = header;
  image.height = static_cast<std::uint32_t>(bgr.rows);
  image.width = static_cast<std::uint32_t>(bgr.cols);
  image.encoding = "bgr8";
  image.step = image.width * 3;
  image.data.resize(static_cast<std::size_t>(image.step) * image.height);
  for (int v = 0; v < bgr.rows; ++v) std::memcpy(&image.data[v * image.step], bgr.ptr(v), image.step);

  sensor_msgs::PointCloud2& points = m.cloud;
  points.header = header;
  points.height = static_cast<std::uint32_t>(cloud.rows);
  points.width = static_cast<std::uint32_t>(cloud.cols);
  const char* names[3] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i) {
    sensor_msgs::PointField f;
    f.name = names[i];
    f.offset = static_cast<std::uint32_t>(4 * i);
    f.datatype = sensor_msgs::PointField::FLOAT32;
    f.count = 1;
    points.fields.push_back(f);
  }
  points.is_bigendian = false;
  points.point_step = 12;
  points.row_step = points.point_step * points.width;
  points.is_dense = false;
  points.data.resize(static_cast<std::size_t>(points.row_step) * points.height);
  for (int v = 0; v < cloud.rows; ++v) std::memcpy(&points.data[v * points.row_step], cloud.ptr(v), points.row_step);

  sensor_msgs::CameraInfo& info = m.info;
  info.header = header;
  info.width = image.width;
  info.height = image.height;
  info.distortion_model = "plumb_bob";
  info.D.assign(5, 0.0);
  info.K = {p.fx, 0.0, p.cx, 0.0, p.fx, p.cy, 0.0, 0.0, 1.0};
  info.R = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
  info.P = {p.fx, 0.0, p.cx, 0.0, 0.0, p.fx, p.cy, 0.0, 0.0, 0.0, 1.0, 0.0};
  return m;
}

}  // namespace sim
}  // namespace cotton_harvester
