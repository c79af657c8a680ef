#include "ros_conversions.h"

#include <cmath>

#include <tf2/LinearMath/Matrix3x3.h>
#include <tf2/LinearMath/Quaternion.h>

namespace thorvald_navigation {
namespace {

double yawOf(double x, double y, double z, double w) {
  tf2::Quaternion q(x, y, z, w);
  if (!(q.length2() > 1e-12) || !std::isfinite(q.length2())) return std::nan("");
  q.normalize();
  double roll, pitch, yaw;
  tf2::Matrix3x3(q).getRPY(roll, pitch, yaw);
  return yaw;
}

}  // namespace

Pose2D fromPose(const geometry_msgs::Pose& p) {
  return {p.position.x, p.position.y, yawOf(p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w)};
}

Pose2D fromTransform(const geometry_msgs::Transform& t) {
  return {t.translation.x, t.translation.y, yawOf(t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w)};
}

geometry_msgs::Pose toPose(const Pose2D& p) {
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

geometry_msgs::Transform toTransform(const Pose2D& p) {
  const geometry_msgs::Pose pose = toPose(p);
  geometry_msgs::Transform t;
  t.translation.x = pose.position.x;
  t.translation.y = pose.position.y;
  t.rotation = pose.orientation;
  return t;
}

std::string fromGridMessage(const nav_msgs::OccupancyGrid& msg, Grid2D* grid) {
  const auto& info = msg.info;
  if (static_cast<std::size_t>(info.width) * info.height != msg.data.size()) return "width x height != data size";
  if (info.width == 0 || info.height == 0) return "empty grid";
  if (!(info.resolution > 0.0f) || !std::isfinite(info.resolution)) return "resolution must be > 0";
  const Pose2D o = fromPose(info.origin);
  if (!o.finite() || std::abs(o.yaw) > 1e-6) return "origin must be finite and not rotated";
  Grid2D g(static_cast<int>(info.width), static_cast<int>(info.height), info.resolution, o.x, o.y);
  for (std::size_t i = 0; i < msg.data.size(); ++i) g.data[i] = msg.data[i];
  *grid = std::move(g);
  return {};
}

nav_msgs::OccupancyGrid toGridMessage(const Grid2D& grid, const std::string& frame_id) {
  nav_msgs::OccupancyGrid m;
  m.header.frame_id = frame_id;
  m.info.resolution = static_cast<float>(grid.resolution_m);
  m.info.width = static_cast<std::uint32_t>(grid.width);
  m.info.height = static_cast<std::uint32_t>(grid.height);
  m.info.origin = toPose({grid.origin_x_m, grid.origin_y_m, 0.0});
  m.data.assign(grid.data.begin(), grid.data.end());
  return m;
}

std::string scanToPoints(const sensor_msgs::LaserScan& scan, const Pose2D& sensor_in_base, double max_range,
                         ScanPoints* out) {
  out->hits.clear();
  out->free_ends.clear();
  out->dropped = 0;
  if (!std::isfinite(scan.angle_min) || !std::isfinite(scan.angle_increment) || scan.angle_increment == 0.0f)
    return "angle_min and angle_increment must be finite and angle_increment != 0";
  if (scan.ranges.size() > 100000) return "more than 100000 beams";
  if (!std::isfinite(scan.range_max) || !(scan.range_max > 0.0f)) return "range_max must be > 0";
  const double limit = std::min<double>(scan.range_max, max_range);
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    const double r = scan.ranges[i];
    const double a = scan.angle_min + static_cast<double>(i) * scan.angle_increment;
    const Eigen::Vector2d dir(std::cos(a), std::sin(a));
    if (std::isinf(r) && r > 0.0) {  // REP 117: +inf means nothing within range
      out->free_ends.push_back(sensor_in_base.transform(dir * limit));
    } else if (!std::isfinite(r) || r < scan.range_min) {
      ++out->dropped;
    } else if (r >= limit) {
      out->free_ends.push_back(sensor_in_base.transform(dir * limit));
    } else {
      out->hits.push_back(sensor_in_base.transform(dir * r));
    }
  }
  return {};
}

}  // namespace thorvald_navigation
