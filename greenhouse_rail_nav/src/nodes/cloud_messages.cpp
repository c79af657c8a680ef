#include "cloud_messages.h"

#include <cstring>

#include <sensor_msgs/point_cloud2_iterator.h>

namespace greenhouse_rail_nav {

bool fromMessage(const sensor_msgs::PointCloud2& msg, OrganisedCloud* cloud, std::string* error) {
  int offset[3] = {-1, -1, -1};
  const char* names[3] = {"x", "y", "z"};
  for (const auto& field : msg.fields) {
    for (int i = 0; i < 3; ++i) {
      if (field.name != names[i]) continue;
      if (field.datatype != sensor_msgs::PointField::FLOAT32) {
        *error = std::string("field ") + names[i] + " is not FLOAT32";
        return false;
      }
      offset[i] = static_cast<int>(field.offset);
    }
  }
  for (int i = 0; i < 3; ++i) {
    if (offset[i] < 0) {
      *error = std::string("no field ") + names[i];
      return false;
    }
    if (static_cast<std::uint32_t>(offset[i]) + 4 > msg.point_step) {
      *error = "field offsets beyond point_step";
      return false;
    }
  }
  const std::size_t rows = msg.height, cols = msg.width;
  if (msg.row_step < cols * msg.point_step || msg.data.size() < rows * msg.row_step) {
    *error = "data shorter than height x row_step (or row_step < width x point_step)";
    return false;
  }
  cloud->width = static_cast<int>(cols);
  cloud->height = static_cast<int>(rows);
  cloud->points.resize(rows * cols);
  for (std::size_t r = 0; r < rows; ++r) {
    const std::uint8_t* row = msg.data.data() + r * msg.row_step;
    for (std::size_t c = 0; c < cols; ++c) {
      const std::uint8_t* p = row + c * msg.point_step;
      float xyz[3];
      for (int i = 0; i < 3; ++i) std::memcpy(&xyz[i], p + offset[i], sizeof(float));
      cloud->points[r * cols + c] = Eigen::Vector3f(xyz[0], xyz[1], xyz[2]);
    }
  }
  return true;
}

sensor_msgs::PointCloud2 toMessage(const OrganisedCloud& cloud, const std::string& frame_id, const ros::Time& stamp) {
  sensor_msgs::PointCloud2 msg;
  msg.header.frame_id = frame_id;
  msg.header.stamp = stamp;
  sensor_msgs::PointCloud2Modifier modifier(msg);
  modifier.setPointCloud2FieldsByString(1, "xyz");
  msg.height = static_cast<std::uint32_t>(cloud.height);
  msg.width = static_cast<std::uint32_t>(cloud.width);
  msg.row_step = msg.width * msg.point_step;
  msg.data.resize(static_cast<std::size_t>(msg.row_step) * msg.height);
  msg.is_dense = false;
  for (std::size_t i = 0; i < cloud.points.size(); ++i) {
    std::memcpy(msg.data.data() + i * msg.point_step, cloud.points[i].data(), 3 * sizeof(float));
  }
  return msg;
}

}  // namespace greenhouse_rail_nav
