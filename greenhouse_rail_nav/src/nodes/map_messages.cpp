#include "map_messages.h"

#include <algorithm>
#include <cmath>

#include "thorvald_map/ros/conversions.h"

namespace greenhouse_rail_nav {
namespace {

geometry_msgs::Point point(const Eigen::Vector2d& p, double z = 0.05) {
  geometry_msgs::Point out;
  out.x = p.x();
  out.y = p.y();
  out.z = z;
  return out;
}

visualization_msgs::Marker marker(const std::string& ns, int id, int type, const std::string& frame_id,
                                  const ros::Time& stamp, float r, float g, float b, double width) {
  visualization_msgs::Marker m;
  m.header.frame_id = frame_id;
  m.header.stamp = stamp;
  m.ns = ns;
  m.id = id;
  m.type = type;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = width;
  m.scale.y = width;
  m.scale.z = width;
  m.color.r = r;
  m.color.g = g;
  m.color.b = b;
  m.color.a = 1.0f;
  return m;
}

}  // namespace

visualization_msgs::MarkerArray analysisMarkers(const MapAnalysis& analysis, double rail_gauge_m,
                                                const std::string& frame_id, const ros::Time& stamp) {
  using visualization_msgs::Marker;
  visualization_msgs::MarkerArray array;
  Marker clear;
  clear.action = Marker::DELETEALL;
  array.markers.push_back(clear);
  // Every straight line found (grey), the rear wall (blue), rows (green).
  Marker lines = marker("lines", 0, Marker::LINE_LIST, frame_id, stamp, 0.6f, 0.6f, 0.6f, 0.05);
  Marker rows = marker("rows", 0, Marker::LINE_LIST, frame_id, stamp, 0.1f, 0.8f, 0.1f, 0.08);
  Marker wall = marker("rear_wall", 0, Marker::LINE_LIST, frame_id, stamp, 0.2f, 0.3f, 1.0f, 0.10);
  for (std::size_t i = 0; i < analysis.lines.size(); ++i) {
    const auto& fit = analysis.lines[i].fit;
    const bool is_row =
        std::find(analysis.rows.begin(), analysis.rows.end(), static_cast<int>(i)) != analysis.rows.end();
    Marker& target = static_cast<int>(i) == analysis.rear_wall ? wall : (is_row ? rows : lines);
    target.points.push_back(point(fit.centroid + fit.s_min * fit.direction));
    target.points.push_back(point(fit.centroid + fit.s_max * fit.direction));
  }
  for (Marker* m : {&lines, &rows, &wall})
    if (!m->points.empty()) array.markers.push_back(*m);
  if (!analysis.ok) return array;
  // Headland edge (the virtual wall), red; side wall hits, orange spheres.
  Marker edge = marker("headland_edge", 0, Marker::LINE_STRIP, frame_id, stamp, 1.0f, 0.1f, 0.1f, 0.10);
  edge.points = {point(analysis.edge_start), point(analysis.edge_end)};
  array.markers.push_back(edge);
  Marker walls = marker("side_walls", 0, Marker::SPHERE_LIST, frame_id, stamp, 1.0f, 0.6f, 0.0f, 0.3);
  if (analysis.left_wall_found) walls.points.push_back(point(analysis.left_wall));
  if (analysis.right_wall_found) walls.points.push_back(point(analysis.right_wall));
  if (!walls.points.empty()) array.markers.push_back(walls);
  // Per rail set: the two rails' first metre (yellow), the target pose (red arrow), its index.
  Marker rails = marker("rails", 0, Marker::LINE_LIST, frame_id, stamp, 1.0f, 0.9f, 0.0f, 0.05);
  for (const auto& set : analysis.rail_sets) {
    for (const double side : {-0.5, 0.5}) {
      rails.points.push_back(point(set.rail_frame.transformPoint({0.0, side * rail_gauge_m})));
      rails.points.push_back(point(set.rail_frame.transformPoint({1.0, side * rail_gauge_m})));
    }
    Marker arrow = marker("targets", set.index, Marker::ARROW, frame_id, stamp, 1.0f, 0.0f, 0.0f, 0.1);
    arrow.pose = thorvald_map::toPose(set.target_pose);
    arrow.scale.x = 0.6;
    arrow.scale.y = 0.08;
    arrow.scale.z = 0.08;
    array.markers.push_back(arrow);
    Marker text = marker("target_index", set.index, Marker::TEXT_VIEW_FACING, frame_id, stamp, 1.0f, 1.0f, 1.0f, 0.3);
    text.pose = thorvald_map::toPose(set.target_pose);
    text.pose.position.z = 0.4;
    text.text = std::to_string(set.index);
    array.markers.push_back(text);
  }
  array.markers.push_back(rails);
  return array;
}

}  // namespace greenhouse_rail_nav
