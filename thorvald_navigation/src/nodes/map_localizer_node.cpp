// map_localizer: localises base_link in a stored map from lidar scans and odometry, with AMCL's interface
// (initialpose, amcl_pose, map -> odom on tf, global_localization, request_nomotion_update). Thin shell around
// MapLocalizer; no particles, so no particlecloud.
#include <chrono>
#include <cmath>
#include <mutex>
#include <string>

#include <diagnostic_updater/diagnostic_updater.h>
#include <geometry_msgs/PoseWithCovarianceStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/OccupancyGrid.h>
#include <ros/ros.h>
#include <sensor_msgs/LaserScan.h>
#include <std_msgs/String.h>
#include <std_srvs/Empty.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>
#include <thorvald_common/ros/param_reader.h>

#include "ros_conversions.h"
#include "scan_frames.h"
#include "thorvald_map/map_file.h"
#include "thorvald_navigation/map_localizer.h"

namespace thorvald_navigation {
namespace {

struct Settings {
  std::string base_frame_id = "base_link", odom_frame_id = "odom", global_frame_id = "map";
  std::string map_file;           // empty: take the map from the `map` topic
  bool use_wall_surface = false;  // match at the map file's wall surface, when it names one
  bool tf_broadcast = true;
  double transform_tolerance = 0.1;
  double laser_max_range = 30.0;
  double tf_timeout = 0.1;
  bool have_initial_pose = false;
  thorvald_base::Pose2D initial_pose;
  double initial_search_xy = 0.5, initial_search_yaw = 0.35;
  LocalizerParams loc;
};

/// Reads and checks the node's parameters; false with the reason in `error` when one is wrong.
bool loadSettings(const ros::NodeHandle& pnh, Settings* s, std::string* error) {
  using R = thorvald_common::ParamRange;
  try {
    thorvald_common::ParamReader r(pnh, "map_localizer");
    s->base_frame_id = r.text("base_frame_id", s->base_frame_id);
    s->odom_frame_id = r.text("odom_frame_id", s->odom_frame_id);
    s->global_frame_id = r.text("global_frame_id", s->global_frame_id);
    s->map_file = r.text("map_file", s->map_file);
    s->use_wall_surface = r.flag("use_wall_surface", s->use_wall_surface);
    s->tf_broadcast = r.flag("tf_broadcast", s->tf_broadcast);
    s->transform_tolerance = r.number("transform_tolerance", s->transform_tolerance, R::closed(0.0, 10.0), "s");
    s->laser_max_range = r.number("laser_max_range", s->laser_max_range, R::above(0.0), "m");
    s->tf_timeout = r.number("tf_timeout", s->tf_timeout, R::closed(0.0, 5.0), "s");
    s->have_initial_pose = r.has("initial_pose_x") || r.has("initial_pose_y");
    s->initial_pose.x = r.number("initial_pose_x", s->initial_pose.x, R::closed(-1e4, 1e4), "m");
    s->initial_pose.y = r.number("initial_pose_y", s->initial_pose.y, R::closed(-1e4, 1e4), "m");
    s->initial_pose.yaw = r.number("initial_pose_a", s->initial_pose.yaw, R::closed(-10.0, 10.0), "rad");
    s->initial_search_xy = r.number("initial_search_xy", s->initial_search_xy, R::atLeast(0.0), "m");
    s->initial_search_yaw = r.number("initial_search_yaw", s->initial_search_yaw, R::aboveUpTo(0.0, 3.1416), "rad");
    auto& l = s->loc;
    l.max_beams = r.integer("laser_max_beams", l.max_beams, 2, 100000);
    l.field_max_distance_m = r.number("laser_likelihood_max_dist", l.field_max_distance_m, R::above(0.0), "m");
    l.matcher.sigma_hit_m = r.number("laser_sigma_hit", l.matcher.sigma_hit_m, R::above(0.0), "m");
    l.odom_sigma_xy_m = r.number("odom_sigma_xy", l.odom_sigma_xy_m, R::above(0.0), "m");
    l.odom_sigma_per_m = r.number("odom_sigma_per_m", l.odom_sigma_per_m, R::atLeast(0.0));
    l.odom_sigma_yaw_rad = r.number("odom_sigma_yaw", l.odom_sigma_yaw_rad, R::above(0.0), "rad");
    l.odom_sigma_yaw_per_rad = r.number("odom_sigma_yaw_per_rad", l.odom_sigma_yaw_per_rad, R::atLeast(0.0));
    l.uncertain_inlier_fraction =
        r.number("uncertain_inlier_fraction", l.uncertain_inlier_fraction, R::closed(0.0, 1.0));
    l.lost_inlier_fraction = r.number("lost_inlier_fraction", l.lost_inlier_fraction, R::closed(0.0, 1.0));
    l.lost_after_scans = r.integer("lost_after_scans", l.lost_after_scans, 1, 100000);
    l.max_jump_m = r.number("max_jump", l.max_jump_m, R::above(0.0), "m");
    l.recheck_xy_m = r.number("recheck_xy", l.recheck_xy_m, R::closed(0.0, 20.0), "m");
    l.recheck_yaw_rad = r.number("recheck_yaw", l.recheck_yaw_rad, R::aboveUpTo(0.0, 3.1416), "rad");
    l.recheck_every_scans = r.integer("recheck_every_scans", l.recheck_every_scans, 1, 100000);
    l.recheck_inlier_fraction = r.number("recheck_inlier_fraction", l.recheck_inlier_fraction, R::closed(0.0, 1.0));
    l.global.step_xy_m = r.number("global_step_xy", l.global.step_xy_m, R::above(0.0), "m");
    l.global.step_yaw_rad = r.number("global_step_yaw", l.global.step_yaw_rad, R::aboveUpTo(0.0, 1.0), "rad");
    // AMCL's particle-filter tuning: accepted, no meaning for scan matching with an odometry prior.
    for (const char* key : {"min_particles",       "max_particles",       "kld_err",           "kld_z",
                            "update_min_d",        "update_min_a",        "resample_interval", "recovery_alpha_slow",
                            "recovery_alpha_fast", "gui_publish_rate",    "save_pose_rate",    "use_map_topic",
                            "first_map_only",      "laser_z_hit",         "laser_z_short",     "laser_z_max",
                            "laser_z_rand",        "laser_lambda_short",  "laser_model_type",  "odom_model_type",
                            "odom_alpha1",         "odom_alpha2",         "odom_alpha3",       "odom_alpha4",
                            "odom_alpha5",         "initial_cov_xx",      "initial_cov_yy",    "initial_cov_aa",
                            "laser_min_range",     "selective_resampling"})
      r.alsoRead(key);
    r.finish();
    const std::string problem = l.validate();
    if (!problem.empty()) throw thorvald_common::ParamError("map_localizer: " + problem);
  } catch (const thorvald_common::ParamError& e) {
    *error = e.what();
    return false;
  }
  return true;
}

class MapLocalizerNode {
 public:
  MapLocalizerNode(ros::NodeHandle& nh, ros::NodeHandle& pnh, const Settings& s)
      : s_(s), loc_(s.loc), tf_listener_(tf_buffer_), frames_(tf_buffer_), updater_(nh, pnh) {
    pose_pub_ = nh.advertise<geometry_msgs::PoseWithCovarianceStamped>("amcl_pose", 2, true);
    status_pub_ = pnh.advertise<std_msgs::String>("status", 1, true);
    scan_sub_ = nh.subscribe("scan", 1, &MapLocalizerNode::onScan, this);
    initial_sub_ = nh.subscribe("initialpose", 2, &MapLocalizerNode::onInitialPose, this);
    global_srv_ = nh.advertiseService("global_localization", &MapLocalizerNode::onGlobal, this);
    nomotion_srv_ = nh.advertiseService("request_nomotion_update", &MapLocalizerNode::onNoMotion, this);
    tf_timer_ = nh.createTimer(ros::Duration(0.05), [this](const ros::TimerEvent&) { publishTf(); });
    updater_.setHardwareID("map_localizer");
    updater_.add("localisation", this, &MapLocalizerNode::diagnose);
    if (s_.have_initial_pose) pending_initial_ = true;
  }

  /// Loads ~map_file, or subscribes to `map`. False with `error` when the file is unusable.
  bool startMap(ros::NodeHandle& nh, std::string* error) {
    if (s_.map_file.empty()) {
      map_sub_ = nh.subscribe("map", 1, &MapLocalizerNode::onMap, this);
      return true;
    }
    thorvald_map::OccupancyGrid g;
    thorvald_map::MapLoadOptions unrotated;
    unrotated.allow_rotated_origin = false;
    if (!thorvald_map::loadMap(s_.map_file, &g, error, unrotated)) return false;
    *error = setMap(g, g.surface.empty() || !s_.use_wall_surface ? nullptr : &g.surface);
    return error->empty();
  }

 private:
  /// `surface`: the map file's wall surface (scans matched to the walls' sub-cell surface), or none.
  std::string setMap(const thorvald_map::OccupancyGrid& g, const thorvald_map::WallSurface* surface = nullptr) {
    std::lock_guard<std::mutex> lock(mutex_);
    const std::string e = loc_.setMap(g, surface);
    if (e.empty())
      ROS_INFO("map_localizer: map %d x %d at %.3f m, walls matched at %s", g.width, g.height, g.resolution_m,
               surface ? "their sub-cell surface (wall_surface file)"
                       : "cell centres (no wall_surface file, or ~use_wall_surface false)");
    return e;
  }

  void onMap(const nav_msgs::OccupancyGrid::ConstPtr& msg) {
    thorvald_map::OccupancyGrid g;
    std::string e;
    if (thorvald_map::fromGridMessage(*msg, &g, &e, /*unrotated=*/true)) e = setMap(g);
    if (!e.empty()) ROS_ERROR_STREAM("map_localizer: map rejected: " << e);
  }

  void onInitialPose(const geometry_msgs::PoseWithCovarianceStamped::ConstPtr& msg) {
    const thorvald_base::Pose2D p = thorvald_map::fromPose(msg->pose.pose);
    if (!p.finite()) {
      ROS_WARN("map_localizer: initialpose with a non-finite pose ignored");
      return;
    }
    if (!msg->header.frame_id.empty() && msg->header.frame_id != s_.global_frame_id) {
      ROS_WARN_STREAM("map_localizer: initialpose in frame '" << msg->header.frame_id << "' ignored: expected '"
                                                              << s_.global_frame_id << "'");
      return;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    s_.initial_pose = p;
    pending_initial_ = true;
    ROS_INFO("map_localizer: initial pose (%.2f, %.2f, %.2f), searched within %.2f m / %.2f rad on the next scan", p.x,
             p.y, p.yaw, s_.initial_search_xy, s_.initial_search_yaw);
  }

  bool onGlobal(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
    std::lock_guard<std::mutex> lock(mutex_);
    loc_.requestGlobalLocalization();
    ROS_INFO("map_localizer: global localisation on the next scan");
    return true;
  }

  bool onNoMotion(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
    force_publish_ = true;
    return true;
  }

  void onScan(const sensor_msgs::LaserScan::ConstPtr& msg) {
    const auto t0 = std::chrono::steady_clock::now();
    std::string error;
    thorvald_base::Pose2D sensor, odom;
    if (!frames_.mount(s_.base_frame_id, msg->header.frame_id, &sensor, &error) ||
        !frames_.lookup(s_.odom_frame_id, s_.base_frame_id, msg->header.stamp, s_.tf_timeout, &odom, &error)) {
      ++rejected_;
      ROS_WARN_STREAM_THROTTLE(5.0, "map_localizer: scan skipped, no transform: " << error);
      return;
    }
    ScanPoints pts;
    error = scanToPoints(*msg, sensor, s_.laser_max_range, &pts);
    if (!error.empty()) {
      ++rejected_;
      ROS_WARN_STREAM_THROTTLE(5.0, "map_localizer: scan rejected: " << error);
      return;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    if (!loc_.hasMap()) {
      ROS_WARN_THROTTLE(10.0, "map_localizer: no map yet");
      return;
    }
    if (pending_initial_) {  // a rough pose from a user: search around it, then track
      pending_initial_ = false;
      loc_.setPose(s_.initial_pose, odom);
      if (s_.initial_search_xy > 0.0) {
        loc_.requestWindowedSearch(s_.initial_pose, s_.initial_search_xy, s_.initial_search_yaw);
      }
    }
    const LocalizationUpdate u = loc_.update(odom, pts.hits);
    if (!u.message.empty() && u.used) ROS_INFO_STREAM("map_localizer: " << u.message);
    if (!u.used && !u.message.empty()) ROS_WARN_STREAM_THROTTLE(2.0, "map_localizer: " << u.message);
    if (u.status != last_status_) {
      std_msgs::String st;
      st.data = statusName(u.status);
      status_pub_.publish(st);
      if (u.status == LocalizationStatus::kLost || u.status == LocalizationStatus::kUncertain) {
        ROS_WARN_STREAM("map_localizer: " << st.data << " (" << u.inlier_fraction * 100.0 << "% of beams matched)");
      } else {
        ROS_INFO_STREAM("map_localizer: " << st.data);
      }
      last_status_ = u.status;
    }
    last_inliers_ = u.inlier_fraction;
    last_scan_stamp_ = msg->header.stamp;
    if (loc_.hasPose() && (u.used || force_publish_)) {
      force_publish_ = false;
      geometry_msgs::PoseWithCovarianceStamped out;
      out.header.stamp = msg->header.stamp;
      out.header.frame_id = s_.global_frame_id;
      out.pose.pose = thorvald_map::toPose(u.pose);
      const int idx[3] = {0, 1, 5};
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) out.pose.covariance[idx[i] * 6 + idx[j]] = u.covariance(i, j);
      pose_pub_.publish(out);
    }
    cpu_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  }

  void publishTf() {
    updater_.update();
    if (!s_.tf_broadcast) return;
    thorvald_base::Pose2D map_to_odom;
    ros::Time stamp;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!loc_.hasPose()) return;
      map_to_odom = loc_.mapToOdom();
      stamp = last_scan_stamp_;
    }
    geometry_msgs::TransformStamped t;
    t.header.stamp = ros::Time::now() + ros::Duration(s_.transform_tolerance);  // AMCL's future-dating
    t.header.frame_id = s_.global_frame_id;
    t.child_frame_id = s_.odom_frame_id;
    t.transform = thorvald_map::toTransform(map_to_odom);
    tf_broadcaster_.sendTransform(t);
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& st) {
    std::lock_guard<std::mutex> lock(mutex_);
    const LocalizationStatus s = loc_.status();
    using D = diagnostic_msgs::DiagnosticStatus;
    if (!loc_.hasMap()) {
      st.summary(D::ERROR, "no map");
    } else if (s == LocalizationStatus::kLocalized) {
      st.summary(D::OK, "localized");
    } else if (s == LocalizationStatus::kLost) {
      st.summary(D::ERROR, "lost: scans do not match the map");
    } else {
      st.summary(D::WARN, statusName(s));
    }
    st.add("beams matched [%]", 100.0 * last_inliers_);
    st.add("scans rejected", rejected_);
    st.add("last scan processing [ms]", cpu_ms_);
  }

  Settings s_;
  std::mutex mutex_;  // loc_ is shared by the scan callback, services and the tf timer
  MapLocalizer loc_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;
  FrameLookup frames_;
  diagnostic_updater::Updater updater_;
  ros::Publisher pose_pub_, status_pub_;
  ros::Subscriber scan_sub_, initial_sub_, map_sub_;
  ros::ServiceServer global_srv_, nomotion_srv_;
  ros::Timer tf_timer_;
  ros::Time last_scan_stamp_;
  bool pending_initial_ = false;
  bool force_publish_ = false;
  LocalizationStatus last_status_ = LocalizationStatus::kNoPose;
  long rejected_ = 0;
  double last_inliers_ = 0.0, cpu_ms_ = 0.0;
};

}  // namespace
}  // namespace thorvald_navigation

int main(int argc, char** argv) {
  ros::init(argc, argv, "map_localizer");
  ros::NodeHandle nh, pnh("~");
  thorvald_navigation::Settings settings;
  std::string error;
  if (!thorvald_navigation::loadSettings(pnh, &settings, &error)) {
    ROS_FATAL_STREAM(error);
    return 1;
  }
  thorvald_navigation::MapLocalizerNode node(nh, pnh, settings);
  if (!node.startMap(nh, &error)) {
    ROS_FATAL_STREAM("map_localizer: " << error);
    return 1;
  }
  ros::spin();
  return 0;
}
