#include "cloud_messages.h"

#include <cstring>

#include <sensor_msgs/point_cloud2_iterator.h>
#include <thorvald_base/ros/organised_cloud.h>

namespace greenhouse_rail_nav {

bool fromMessage(const sensor_msgs::PointCloud2& msg, OrganisedCloud* cloud, std::string* error) {
  thorvald_base::OrganisedCloudView view;
  if (!view.reset(msg, error)) return false;
  cloud->width = view.width();
  cloud->height = view.height();
  cloud->points.resize(static_cast<std::size_t>(view.width()) * static_cast<std::size_t>(view.height()));
  for (int v = 0; v < view.height(); ++v)
    for (int u = 0; u < view.width(); ++u)
      cloud->points[static_cast<std::size_t>(v) * view.width() + u] = view.at(u, v);
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
