#include "zone_watch.h"

#include <tf2/utils.h>
#include <visualization_msgs/MarkerArray.h>

#include <cmath>

#include "thorvald_map/ros/conversions.h"

namespace greenhouse_rail_nav {

void ZoneWatch::readParams(thorvald_common::ParamReader& params, Config* c) {
  using R = thorvald_common::ParamRange;
  ZoneParams& z = c->zone;
  z.cluster_gap_m = params.number("zone/cluster_gap", z.cluster_gap_m, R::aboveUpTo(0.0, 2.0), "m");
  z.min_cluster_points = params.integer("zone/min_cluster_points", z.min_cluster_points, 1, 1000);
  z.person_min_width_m = params.number("zone/person_min_width", z.person_min_width_m, R::closed(0.0, 2.0), "m");
  z.person_max_width_m = params.number("zone/person_max_width", z.person_max_width_m, R::aboveUpTo(0.0, 5.0), "m");
  z.person_min_depth_m = params.number("zone/person_min_depth", z.person_min_depth_m, R::closed(0.0, 1.0), "m");
  z.person_max_fit_rms_m =
      params.number("zone/person_max_fit_rms", z.person_max_fit_rms_m, R::aboveUpTo(0.0, 0.5), "m");
  z.person_fit_outlier_m =
      params.number("zone/person_fit_outlier", z.person_fit_outlier_m, R::aboveUpTo(0.0, 1.0), "m");
  z.person_min_inliers = params.number("zone/person_min_inliers", z.person_min_inliers, R::aboveUpTo(0.0, 1.0));
  z.person_confirm_scans = params.integer("zone/person_confirm_scans", z.person_confirm_scans, 1, 40);
  z.person_confirm_radius_m =
      params.number("zone/person_confirm_radius", z.person_confirm_radius_m, R::aboveUpTo(0.0, 2.0), "m");
  z.headland_radius_m = params.number("zone/headland_radius", z.headland_radius_m, R::closed(0.0, 10.0), "m");
  z.map_clearance_m = params.number("zone/map_clearance", z.map_clearance_m, R::closed(0.0, 1.0), "m");
  z.row_half_width_m = params.number("zone/row_half_width", z.row_half_width_m, R::aboveUpTo(0.0, 2.0), "m");
  z.row_edge_band_m = params.number("zone/row_edge_band", z.row_edge_band_m, R::closed(0.0, 1.0), "m");
  z.row_lamps_radius_m = params.number("zone/row_lamps_radius", z.row_lamps_radius_m, R::closed(0.0, 10.0), "m");
  z.row_ends_margin_m = params.number("zone/row_ends_margin", z.row_ends_margin_m, R::closed(0.0, 10.0), "m");
  z.end_tolerance_m = params.number("zone/end_tolerance", z.end_tolerance_m, R::closed(0.0, 10.0), "m");
  z.row_ahead_m = params.number("zone/row_ahead", z.row_ahead_m, R::aboveUpTo(0.0, 1000.0), "m");
  z.structure_min_length_m =
      params.number("zone/structure_min_length", z.structure_min_length_m, R::closed(0.0, 100.0), "m");
  z.structure_tolerance_m =
      params.number("zone/structure_tolerance", z.structure_tolerance_m, R::aboveUpTo(0.0, 0.5), "m");
  z.structure_gap_m = params.number("zone/structure_gap", z.structure_gap_m, R::aboveUpTo(0.0, 5.0), "m");
  z.structure_max_angle_rad =
      params.number("zone/structure_max_angle", z.structure_max_angle_rad, R::aboveUpTo(0.0, 1.4), "rad");
  z.rear_stop_range_m = params.number("zone/rear_stop_range", z.rear_stop_range_m, R::closed(0.0, 5.0), "m");
  z.rear_clearance_m = params.number("zone/rear_clearance", z.rear_clearance_m, R::closed(0.0, 5.0), "m");
  z.behind_wait_s = params.number("zone/behind_wait", z.behind_wait_s, R::closed(0.0, 3600.0), "s");
  z.clear_time_s = params.number("zone/clear_time", z.clear_time_s, R::closed(0.0, 600.0), "s");
  c->scan_timeout_s = params.number("zone/scan_timeout", c->scan_timeout_s, R::aboveUpTo(0.0, 10.0), "s");
  c->rear_sensors = params.texts("rear_sensors", c->rear_sensors, 0, 8, true);
  c->relay_boards = params.texts("relay_boards", c->relay_boards, 0, 16, true);
}

ZoneWatch::ZoneWatch(ros::NodeHandle& nh, const Config& c, tf2_ros::Buffer& tf)
    : cfg_(c), tf_(tf), confirm_(std::make_unique<PersonConfirmation>(c.zone)) {
  rear_range_.assign(c.rear_sensors.size(), NAN);
  rear_stamp_.assign(c.rear_sensors.size(), ros::Time());
  relay_unknown_.assign(c.relay_boards.size(), -1);
  people_pub_ = nh.advertise<std_msgs::Bool>("people_detected", 5);
  markers_pub_ = nh.advertise<visualization_msgs::MarkerArray>("obstacles", 2);
  subs_.push_back(nh.subscribe("scan", 2, &ZoneWatch::onScan, this));
  subs_.push_back(nh.subscribe("map", 1, &ZoneWatch::onMap, this));
  subs_.push_back(nh.subscribe("keep_out_map", 1, &ZoneWatch::onKeepOut, this));
  for (size_t i = 0; i < c.rear_sensors.size(); ++i)
    subs_.push_back(nh.subscribe<sensor_msgs::Range>(
        "ultrasonic/" + c.rear_sensors[i], 5, [this, i](const sensor_msgs::RangeConstPtr& m) { onRear(i, *m); }));
  for (size_t i = 0; i < c.relay_boards.size(); ++i)
    subs_.push_back(nh.subscribe<std_msgs::Bool>("io/" + c.relay_boards[i] + "/state_unknown", 1,
                                                 [this, i](const std_msgs::BoolConstPtr& m) { onRelay(i, *m); }));
}

void ZoneWatch::setContext(const ZoneContext& ctx) {
  std::lock_guard<std::mutex> l(mutex_);
  ctx_ = ctx;
}

ZoneVerdict ZoneWatch::verdict() {
  std::lock_guard<std::mutex> l(mutex_);
  if (!evaluated_.isZero() && (ros::Time::now() - evaluated_).toSec() <= cfg_.scan_timeout_s) return verdict_;
  ZoneVerdict v;
  v.blocked = true;
  v.why = "no lidar scan evaluated for the protected zone (scan, or its frame's transform to base_link, missing)";
  return v;
}

bool ZoneWatch::lightsInDoubt(std::string* why) {
  std::lock_guard<std::mutex> l(mutex_);
  for (size_t i = 0; i < relay_unknown_.size(); ++i) {
    if (relay_unknown_[i] == 0) continue;
    *why = "io/" + cfg_.relay_boards[i] + (relay_unknown_[i] < 0 ? " not heard yet" : " state_unknown");
    return true;
  }
  return false;
}

void ZoneWatch::onMap(const nav_msgs::OccupancyGrid& m) {
  if (!storeGrid(m, "map", &map_)) return;
  std::lock_guard<std::mutex> l(mutex_);
  have_map_ = true;
}

void ZoneWatch::onKeepOut(const nav_msgs::OccupancyGrid& m) { storeGrid(m, "keep-out grid", &keep_out_); }

bool ZoneWatch::storeGrid(const nav_msgs::OccupancyGrid& m, const char* what, thorvald_map::OccupancyGrid* out) {
  thorvald_map::OccupancyGrid g;
  std::string error;
  if (!thorvald_map::fromGridMessage(m, &g, &error)) {
    ROS_WARN("uv_mission: %s not used for the people detection: %s", what, error.c_str());
    return false;
  }
  std::lock_guard<std::mutex> l(mutex_);
  *out = std::move(g);
  return true;
}

void ZoneWatch::onRear(size_t i, const sensor_msgs::Range& m) {
  std::lock_guard<std::mutex> l(mutex_);
  rear_range_[i] = (m.range >= m.min_range && m.range <= m.max_range) ? m.range : NAN;
  rear_stamp_[i] = ros::Time::now();
}

void ZoneWatch::onRelay(size_t i, const std_msgs::Bool& m) {
  std::lock_guard<std::mutex> l(mutex_);
  relay_unknown_[i] = m.data ? 1 : 0;
}

bool ZoneWatch::toBase(const sensor_msgs::LaserScan& m, std::vector<ScanPoint>* pts, double* lidar_x) {
  thorvald_base::Pose2D lidar;
  try {
    lidar = thorvald_map::fromTransform(
        tf_.lookupTransform(cfg_.base_frame, m.header.frame_id, ros::Time(0), ros::Duration(0.0)).transform);
  } catch (const tf2::TransformException& e) {
    ROS_WARN_THROTTLE(5.0, "uv_mission: no %s -> %s for the people detection: %s", cfg_.base_frame.c_str(),
                      m.header.frame_id.c_str(), e.what());
    return false;
  }
  *lidar_x = lidar.x;
  for (size_t i = 0; i < m.ranges.size(); ++i) {
    const double r = m.ranges[i];
    if (!std::isfinite(r) || r < m.range_min || r > m.range_max) continue;
    const double a = m.angle_min + static_cast<double>(i) * m.angle_increment;
    const Eigen::Vector2d p = lidar.transformPoint(Eigen::Vector2d(r * std::cos(a), r * std::sin(a)));
    pts->push_back({p.x(), p.y()});
  }
  return true;
}

KnownPoint ZoneWatch::knownInMap() {
  thorvald_base::Pose2D base;
  int reach = 0;
  {
    std::lock_guard<std::mutex> l(mutex_);
    if (!have_map_) return {};
    reach = static_cast<int>(std::ceil(cfg_.zone.map_clearance_m / map_.resolution_m));
  }
  try {
    base = thorvald_map::fromTransform(
        tf_.lookupTransform(cfg_.map_frame, cfg_.base_frame, ros::Time(0), ros::Duration(0.0)).transform);
  } catch (const tf2::TransformException&) {
    return [](double, double) { return true; };  // not localised: nothing can be told from the map
  }
  // Read under mutex_, which the caller holds while it evaluates the scan (onMap replaces map_ under it).
  return [this, base, reach](double x, double y) {
    return notHeadland(map_, keep_out_, reach, base.transformPoint(Eigen::Vector2d(x, y)));
  };
}

void ZoneWatch::onScan(const sensor_msgs::LaserScan& m) {
  std::vector<ScanPoint> pts;
  double lidar_x = 0.0;
  if (!toBase(m, &pts, &lidar_x)) return;
  ZoneContext ctx;
  std::vector<double> rear;
  {
    std::lock_guard<std::mutex> l(mutex_);
    ctx = ctx_;
    const ros::Time now = ros::Time::now();
    for (size_t i = 0; i < rear_range_.size(); ++i)
      if (!rear_stamp_[i].isZero() && (now - rear_stamp_[i]).toSec() <= cfg_.rear_timeout_s)
        rear.push_back(rear_range_[i]);
  }
  const KnownPoint known = ctx.phase == ZonePhase::kRow ? KnownPoint() : knownInMap();
  ZoneVerdict v;
  {
    std::lock_guard<std::mutex> l(mutex_);  // map_ stays as it is while `known` reads it
    v = evaluateZone(pts, lidar_x, ctx, cfg_.zone, known, rear);
    confirm_->apply(ctx.phase, &v);
    verdict_ = v;
    evaluated_ = ros::Time::now();
  }
  std_msgs::Bool b;
  b.data = v.person || v.blocked;
  people_pub_.publish(b);
  if ((m.header.stamp - last_markers_).toSec() >= 0.2 || m.header.stamp < last_markers_) {
    last_markers_ = m.header.stamp;
    publishMarkers(v, ctx, m.header.stamp);
  }
}

void ZoneWatch::publishMarkers(const ZoneVerdict& v, const ZoneContext& ctx, const ros::Time& stamp) {
  if (markers_pub_.getNumSubscribers() == 0) return;
  visualization_msgs::MarkerArray a;
  visualization_msgs::Marker clear;
  clear.action = visualization_msgs::Marker::DELETEALL;
  a.markers.push_back(clear);
  for (size_t i = 0; i < v.clusters.size(); ++i) {
    const PointCluster& c = v.clusters[i];
    visualization_msgs::Marker k;
    k.header.frame_id = cfg_.base_frame;
    k.header.stamp = stamp;
    k.ns = std::string("uv_mission_") + toString(ctx.phase);
    k.id = static_cast<int>(i);
    k.type = visualization_msgs::Marker::CYLINDER;
    k.pose.position.x = c.x, k.pose.position.y = c.y, k.pose.position.z = 0.9;
    k.pose.orientation.w = 1.0;
    k.scale.x = k.scale.y = std::max(0.1, c.width), k.scale.z = c.person ? 1.8 : 0.5;
    const bool in = i < v.in_zone.size() && v.in_zone[i];
    k.color.r = in ? 1.0f : 0.3f, k.color.g = in ? 0.1f : 0.6f, k.color.b = c.person ? 0.9f : 0.1f;
    k.color.a = 0.6f;
    k.lifetime = ros::Duration(0.5);
    a.markers.push_back(k);
  }
  markers_pub_.publish(a);
}

}  // namespace greenhouse_rail_nav
