// headland_mapper: occupancy mapping of the headland from lidar scans and fused odometry by scan matching to the
// map built so far (gmapping's topics and the parameter names that apply); saves map_server YAML + PGM on
// ~save_map and at shutdown. Thin shell around OccupancyMapper.
#include <chrono>
#include <memory>
#include <mutex>
#include <string>

#include <diagnostic_updater/diagnostic_updater.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/GetMap.h>
#include <nav_msgs/MapMetaData.h>
#include <nav_msgs/OccupancyGrid.h>
#include <ros/ros.h>
#include <sensor_msgs/LaserScan.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>
#include <thorvald_common/ros/param_reader.h>

#include "ros_conversions.h"
#include "scan_frames.h"
#include "thorvald_map/map_file.h"
#include "thorvald_navigation/occupancy_mapper.h"

namespace thorvald_navigation {
namespace {

struct Settings {
  std::string base_frame = "base_link", odom_frame = "odom", map_frame = "map";
  std::string map_file;  // stem; empty: no saving
  double map_update_interval = 2.0;
  double transform_publish_period = 0.05;
  double progress_period = 5.0;
  double tf_timeout = 0.1;
  MapperParams mapper;
};

/// Reads and checks the node's parameters; false with the reason in `error` when one is wrong.
bool loadSettings(const ros::NodeHandle& pnh, Settings* s, std::string* error) {
  using R = thorvald_common::ParamRange;
  try {
    thorvald_common::ParamReader r(pnh, "headland_mapper");
    s->base_frame = r.text("base_frame", s->base_frame);
    s->odom_frame = r.text("odom_frame", s->odom_frame);
    s->map_frame = r.text("map_frame", s->map_frame);
    s->map_file = r.text("map_file", s->map_file);
    s->map_update_interval = r.number("map_update_interval", s->map_update_interval, R::above(0.0), "s");
    s->transform_publish_period =
        r.number("transform_publish_period", s->transform_publish_period, R::aboveUpTo(0.0, 1.0), "s");
    s->progress_period = r.number("progress_period", s->progress_period, R::above(0.0), "s");
    s->tf_timeout = r.number("tf_timeout", s->tf_timeout, R::closed(0.0, 5.0), "s");
    auto& m = s->mapper;
    m.resolution_m = r.number("delta", m.resolution_m, R::closed(0.005, 1.0), "m");
    m.max_range_m = r.number("maxUrange", m.max_range_m, R::above(0.0), "m");
    m.linear_update_m = r.number("linearUpdate", m.linear_update_m, R::atLeast(0.0), "m");
    m.angular_update_rad = r.number("angularUpdate", m.angular_update_rad, R::atLeast(0.0), "rad");
    m.initial_size_m = r.number("initial_size", m.initial_size_m, R::above(0.0), "m");
    m.max_size_m = r.number("max_size", m.max_size_m, R::above(0.0), "m");
    m.matcher.sigma_hit_m = r.number("sigma", m.matcher.sigma_hit_m, R::above(0.0), "m");
    m.min_inlier_fraction = r.number("min_inlier_fraction", m.min_inlier_fraction, R::closed(0.0, 1.0));
    m.odom_sigma_xy_m = r.number("odom_sigma_xy", m.odom_sigma_xy_m, R::atLeast(0.0), "m");
    m.odom_sigma_yaw_rad = r.number("odom_sigma_yaw", m.odom_sigma_yaw_rad, R::atLeast(0.0), "rad");
    m.odom_sigma_fraction = r.number("odom_sigma_fraction", m.odom_sigma_fraction, R::atLeast(0.0));
    m.match_surface = r.flag("match_surface", true);  // the node matches at the wall surface unless told not to
    m.surfel_half_length_m = r.number("surfel_half_length", m.surfel_half_length_m, R::atLeast(0.0), "m");
    m.grazing_keep_max_m = r.number("grazing_keep_max", m.grazing_keep_max_m, R::atLeast(0.0), "m");
    m.no_return_keeps_ends = r.flag("no_return_keeps_ends", m.no_return_keeps_ends);
    m.grazing_neighbour_gap_m = r.number("grazing_neighbour_gap", m.grazing_neighbour_gap_m, R::above(0.0), "m");
    // gmapping's particle-filter tuning: accepted, no meaning for a single scan-matched trajectory.
    for (const char* key : {"particles",
                            "minimumScore",
                            "lskip",
                            "srr",
                            "srt",
                            "str",
                            "stt",
                            "ogain",
                            "kernelSize",
                            "lstep",
                            "astep",
                            "iterations",
                            "lsigma",
                            "resampleThreshold",
                            "temporalUpdate",
                            "llsamplerange",
                            "llsamplestep",
                            "lasamplerange",
                            "lasamplestep",
                            "xmin",
                            "xmax",
                            "ymin",
                            "ymax",
                            "maxRange",
                            "throttle_scans",
                            "occ_thresh"})
      r.alsoRead(key);
    r.finish();
    const std::string problem = m.validate();
    if (!problem.empty()) throw thorvald_common::ParamError("headland_mapper: " + problem);
    if (s->base_frame.empty() || s->odom_frame.empty() || s->map_frame.empty())
      throw thorvald_common::ParamError("headland_mapper: ~base_frame, ~odom_frame and ~map_frame must not be empty");
  } catch (const thorvald_common::ParamError& e) {
    *error = e.what();
    return false;
  }
  return true;
}

class HeadlandMapperNode {
 public:
  HeadlandMapperNode(ros::NodeHandle& nh, ros::NodeHandle& pnh, const Settings& s)
      : s_(s), mapper_(s.mapper), tf_listener_(tf_buffer_), frames_(tf_buffer_), updater_(nh, pnh) {
    map_pub_ = nh.advertise<nav_msgs::OccupancyGrid>("map", 1, true);
    meta_pub_ = nh.advertise<nav_msgs::MapMetaData>("map_metadata", 1, true);
    scan_sub_ = nh.subscribe("scan", 5, &HeadlandMapperNode::onScan, this);
    save_srv_ = pnh.advertiseService("save_map", &HeadlandMapperNode::onSave, this);
    get_map_srv_ = nh.advertiseService("dynamic_map", &HeadlandMapperNode::onGetMap, this);
    map_timer_ =
        nh.createTimer(ros::Duration(s_.map_update_interval), [this](const ros::TimerEvent&) { publishMap(); });
    tf_timer_ =
        nh.createTimer(ros::Duration(s_.transform_publish_period), [this](const ros::TimerEvent&) { publishTf(); });
    progress_timer_ = nh.createTimer(ros::Duration(s_.progress_period), [this](const ros::TimerEvent&) { progress(); });
    updater_.setHardwareID("headland_mapper");
    updater_.add("mapping", this, &HeadlandMapperNode::diagnose);
  }

  /// Saves the map at shutdown (called from main after spinning stops).
  void saveAtShutdown() {
    if (s_.map_file.empty() || mapper_.scansUsed() == 0) return;
    const std::string e = save();
    if (e.empty()) {
      ROS_INFO_STREAM("headland_mapper: map saved to " << s_.map_file << ".yaml at shutdown");
    } else {
      ROS_ERROR_STREAM("headland_mapper: " << e);
    }
  }

 private:
  void onScan(const sensor_msgs::LaserScan::ConstPtr& msg) {
    std::string error;
    thorvald_base::Pose2D sensor, odom;
    if (!frames_.mount(s_.base_frame, msg->header.frame_id, &sensor, &error) ||
        !frames_.lookup(s_.odom_frame, s_.base_frame, msg->header.stamp, s_.tf_timeout, &odom, &error)) {
      ++rejected_;
      ROS_WARN_STREAM_THROTTLE(5.0, "headland_mapper: scan skipped, no transform: " << error);
      return;
    }
    ScanPoints pts;
    error = scanToPoints(*msg, sensor, s_.mapper.max_range_m, &pts);
    if (!error.empty()) {
      ++rejected_;
      ROS_WARN_STREAM_THROTTLE(5.0, "headland_mapper: scan rejected: " << error);
      return;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    // Scans the publisher sent that never reached this callback (the subscriber queue overflowed while a scan was
    // being integrated): gaps in the header's sequence number.
    if (have_seq_ && msg->header.seq > last_seq_) missed_ += msg->header.seq - last_seq_ - 1;
    have_seq_ = true;
    last_seq_ = msg->header.seq;
    const auto t0 = std::chrono::steady_clock::now();
    const MapperUpdate u = mapper_.addScan(odom, {sensor.x, sensor.y}, pts.hits, pts.free_ends);
    if (u.integrated) {
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      integrate_ms_sum_ += ms;
      integrate_ms_max_ = std::max(integrate_ms_max_, ms);
    }
    if (!u.rejected.empty()) {
      ++rejected_;
      ROS_WARN_STREAM_THROTTLE(5.0, "headland_mapper: scan rejected: " << u.rejected);
    }
    if (u.integrated) {
      unmatched_ += u.matched ? 0 : 1;
      last_inliers_ = u.inlier_fraction;
    }
    last_stamp_ = msg->header.stamp;
  }

  void publishTf() {
    updater_.update();  // rate-limited by the updater itself
    thorvald_base::Pose2D map_to_odom;
    ros::Time stamp;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (mapper_.scansUsed() == 0) return;
      map_to_odom = mapper_.mapToOdom();
      stamp = last_stamp_;
    }
    geometry_msgs::TransformStamped t;
    // Future-dated like gmapping, so that lookups at the latest scan time succeed.
    t.header.stamp = ros::Time::now() + ros::Duration(s_.transform_publish_period);
    t.header.frame_id = s_.map_frame;
    t.child_frame_id = s_.odom_frame;
    t.transform = thorvald_map::toTransform(map_to_odom);
    tf_broadcaster_.sendTransform(t);
  }

  nav_msgs::OccupancyGrid currentMap() {
    std::lock_guard<std::mutex> lock(mutex_);
    nav_msgs::OccupancyGrid m = thorvald_map::toGridMessage(mapper_.occupancyGrid(), s_.map_frame);
    m.header.stamp = ros::Time::now();
    m.info.map_load_time = m.header.stamp;
    return m;
  }

  void publishMap() {
    if (mapper_.scansUsed() == 0) return;
    const nav_msgs::OccupancyGrid m = currentMap();
    map_pub_.publish(m);
    meta_pub_.publish(m.info);
  }

  void progress() {
    if (mapper_.scansUsed() == 0) {
      ROS_INFO_STREAM_THROTTLE(
          30.0, "headland_mapper: waiting for scans and " << s_.odom_frame << " -> " << s_.base_frame << " on tf");
      return;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    const int used = mapper_.scansUsed();
    ROS_INFO(
        "headland_mapper: %.1f m2 mapped, %d scans used (%ld placed by odometry alone), %ld missed (queue "
        "full), last match %.0f%%, %.1f ms per integrated scan (max %.1f)",
        mapper_.knownAreaM2(), used, unmatched_, missed_, 100.0 * last_inliers_, integrate_ms_sum_ / used,
        integrate_ms_max_);
  }

  std::string save() {
    thorvald_map::OccupancyGrid g;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      g = mapper_.occupancyGrid();
      g.surface = mapper_.wallSurface();
    }
    std::string error;
    return thorvald_map::saveMap(g, s_.map_file, &error) ? std::string() : error;
  }

  bool onSave(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
    if (s_.map_file.empty()) {
      res.message = "~map_file is not set: nowhere to save";
    } else if (mapper_.scansUsed() == 0) {
      res.message = "no scan integrated yet";
    } else {
      res.message = save();
      res.success = res.message.empty();
      if (res.success) res.message = "saved " + s_.map_file + ".yaml and .pgm";
    }
    ROS_INFO_STREAM("headland_mapper: save_map: " << res.message);
    return true;
  }

  bool onGetMap(nav_msgs::GetMap::Request&, nav_msgs::GetMap::Response& res) {
    res.map = currentMap();
    return true;
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& st) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (mapper_.scansUsed() == 0) {
      st.summary(diagnostic_msgs::DiagnosticStatus::WARN, "no scan integrated yet");
    } else if (last_inliers_ < s_.mapper.min_inlier_fraction) {
      st.summary(diagnostic_msgs::DiagnosticStatus::WARN, "last scan did not match the map: odometry only");
    } else {
      st.summary(diagnostic_msgs::DiagnosticStatus::OK, "mapping");
    }
    st.add("scans used", mapper_.scansUsed());
    st.add("area mapped [m2]", mapper_.knownAreaM2());
    st.add("scans rejected", rejected_);
    st.add("scans placed by odometry alone", unmatched_);
    st.add("scans missed (queue full)", missed_);
  }

  Settings s_;
  std::mutex mutex_;  // mapper_ is written by the scan callback and read by timers and services
  OccupancyMapper mapper_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;
  FrameLookup frames_;
  diagnostic_updater::Updater updater_;
  ros::Publisher map_pub_, meta_pub_;
  ros::Subscriber scan_sub_;
  ros::ServiceServer save_srv_, get_map_srv_;
  ros::Timer map_timer_, tf_timer_, progress_timer_;
  ros::Time last_stamp_;
  long rejected_ = 0, unmatched_ = 0, missed_ = 0;
  bool have_seq_ = false;
  std::uint32_t last_seq_ = 0;
  double integrate_ms_sum_ = 0.0, integrate_ms_max_ = 0.0;
  double last_inliers_ = 0.0;
};

}  // namespace
}  // namespace thorvald_navigation

int main(int argc, char** argv) {
  ros::init(argc, argv, "headland_mapper");
  ros::NodeHandle nh, pnh("~");
  thorvald_navigation::Settings settings;
  std::string error;
  if (!thorvald_navigation::loadSettings(pnh, &settings, &error)) {
    ROS_FATAL_STREAM(error);
    return 1;
  }
  thorvald_navigation::HeadlandMapperNode node(nh, pnh, settings);
  ros::AsyncSpinner spinner(1);  // one thread: callbacks never run concurrently, the mutex guards the services
  spinner.start();
  ros::waitForShutdown();
  node.saveAtShutdown();
  return 0;
}
