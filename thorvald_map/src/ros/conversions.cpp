#include "thorvald_map/ros/conversions.h"

#include <cmath>

#include <tf2/LinearMath/Matrix3x3.h>
#include <tf2/LinearMath/Quaternion.h>

namespace thorvald_map {

double yawOf(const geometry_msgs::Quaternion& q_msg) {
  tf2::Quaternion q(q_msg.x, q_msg.y, q_msg.z, q_msg.w);
  if (!(q.length2() > 1e-12) || !std::isfinite(q.length2())) return std::nan("");
  q.normalize();
  double roll, pitch, yaw;
  tf2::Matrix3x3(q).getRPY(roll, pitch, yaw);
  return yaw;
}

thorvald_base::Pose2D fromPose(const geometry_msgs::Pose& p) {
  return {p.position.x, p.position.y, yawOf(p.orientation)};
}

thorvald_base::Pose2D fromTransform(const geometry_msgs::Transform& t) {
  return {t.translation.x, t.translation.y, yawOf(t.rotation)};
}

geometry_msgs::Pose toPose(const thorvald_base::Pose2D& p) {
  geometry_msgs::Pose out;
  out.position.x = p.x;
  out.position.y = p.y;
  tf2::Quaternion q;
  q.setRPY(0.0, 0.0, p.yaw);
  out.orientation.x = q.x();
  out.orientation.y = q.y();
  out.orientation.z = q.z();
  out.orientation.w = q.w();
  return out;
}

geometry_msgs::Transform toTransform(const thorvald_base::Pose2D& p) {
  const geometry_msgs::Pose pose = toPose(p);
  geometry_msgs::Transform t;
  t.translation.x = pose.position.x;
  t.translation.y = pose.position.y;
  t.rotation = pose.orientation;
  return t;
}

bool fromGridMessage(const nav_msgs::OccupancyGrid& msg, OccupancyGrid* grid, std::string* error, bool unrotated) {
  const auto& info = msg.info;
  thorvald_base::Pose2D origin = fromPose(info.origin);
  if (static_cast<std::uint64_t>(info.width) * info.height != msg.data.size()) {
    *error = "width x height (" + std::to_string(info.width) + " x " + std::to_string(info.height) + ") != data size " +
             std::to_string(msg.data.size());
  } else if (info.width == 0 || info.height == 0) {
    *error = "empty grid";
  } else if (!(info.resolution > 0.0f) || !std::isfinite(info.resolution)) {
    *error = "resolution must be > 0, got " + std::to_string(info.resolution);
  } else if (!origin.finite()) {
    *error = "origin must be finite (position and a usable quaternion)";
  } else if (unrotated && std::abs(origin.yaw) > 1e-6) {
    *error = "origin must not be rotated, got yaw " + std::to_string(origin.yaw);
  } else {
    if (unrotated) origin.yaw = 0.0;
    OccupancyGrid g(static_cast<int>(info.width), static_cast<int>(info.height), info.resolution, origin);
    g.data.assign(msg.data.begin(), msg.data.end());
    *grid = std::move(g);
    return true;
  }
  return false;
}

nav_msgs::OccupancyGrid toGridMessage(const OccupancyGrid& grid, const std::string& frame_id, const ros::Time& stamp) {
  nav_msgs::OccupancyGrid m;
  m.header.frame_id = frame_id;
  m.header.stamp = stamp;
  m.info.map_load_time = stamp;
  m.info.resolution = static_cast<float>(grid.resolution_m);
  m.info.width = static_cast<std::uint32_t>(grid.width);
  m.info.height = static_cast<std::uint32_t>(grid.height);
  m.info.origin = toPose(grid.origin);
  m.data.assign(grid.data.begin(), grid.data.end());
  return m;
}

}  // namespace thorvald_map
