// navsat_transform: GNSS fixes (gps/fix) into the world frame (odometry/gps) for ekf_localization, with
// robot_localization's navsat_transform parameters; the datum from the first fix good enough for it
// (~datum_max_sigma_m; IMU or odometry heading) or from ~datum; each fix moved from the antenna (its frame_id, from
// tf) to base_link with the robot's orientation. Reports a missing, stale or no-fix receiver and the wait for the
// datum on diagnostics. Thin shell around NavsatTransform.
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <diagnostic_updater/diagnostic_updater.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/NavSatFix.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>
#include <thorvald_common/ros/param_reader.h>
#include <thorvald_common/ros/run_node.h>

#include "fusion_conversions.h"
#include "thorvald_navigation/fusion_monitor.h"
#include "thorvald_navigation/navsat_transform.h"

namespace thorvald_navigation {
namespace {

constexpr const char* kGps = "gps/fix";

struct NavsatSettings {
  NavsatOptions options;
  bool broadcast_utm = false, utm_as_parent = false, use_odometry_yaw = false, wait_for_datum = false;
  bool publish_filtered_gps = false;
  std::vector<double> datum;  // [lat deg, lon deg, yaw rad] or empty
  double gps_timeout = 2.0;
  double datum_max_sigma_m = kDatumMaxSigmaM;  // a fix for the datum: horizontal 1-sigma at most this
  std::string world_frame = "odom", base_link_frame = "base_link";
};

NavsatSettings readSettings(ros::NodeHandle& pnh) {
  using R = thorvald_common::ParamRange;
  thorvald_common::ParamReader r(pnh, "navsat_transform");
  NavsatSettings s;
  s.options.magnetic_declination_rad = r.number("magnetic_declination_radians", 0.0, R::closed(-M_PI, M_PI), "rad");
  s.options.yaw_offset_rad = r.number("yaw_offset", 0.0, R::closed(-2 * M_PI, 2 * M_PI), "rad");
  s.options.zero_altitude = r.flag("zero_altitude", false);
  s.broadcast_utm = r.flag("broadcast_utm_transform", false) || r.flag("broadcast_cartesian_transform", false);
  s.utm_as_parent = r.flag("broadcast_utm_transform_as_parent_frame", false) ||
                    r.flag("broadcast_cartesian_transform_as_parent_frame", false);
  s.use_odometry_yaw = r.flag("use_odometry_yaw", false);
  s.wait_for_datum = r.flag("wait_for_datum", false);
  s.publish_filtered_gps = r.flag("publish_filtered_gps", false);
  s.datum = r.numbers("datum", {}, R::any(), "", 0, 3);
  if (!s.datum.empty() && s.datum.size() != 3)
    throw thorvald_common::ParamError("navsat_transform: ~datum: expected [latitude deg, longitude deg, yaw rad]");
  if (s.wait_for_datum && s.datum.empty())
    throw thorvald_common::ParamError(
        "navsat_transform: ~wait_for_datum is true but ~datum is not set (the set_datum service is not implemented)");
  s.gps_timeout = r.number("gps_timeout", s.gps_timeout, R::above(0.0), "s");
  s.datum_max_sigma_m = r.number("datum_max_sigma_m", s.datum_max_sigma_m, R::above(0.0), "m");
  s.world_frame = r.text("world_frame", s.world_frame);
  s.base_link_frame = r.text("base_link_frame", s.base_link_frame);
  r.number("frequency", 10.0, R::above(0.0), "Hz");  // fixes are transformed as they arrive
  std::vector<std::string> ignored;
  for (const char* key : {"delay", "transform_timeout", "use_local_cartesian", "use_manual_datum"})
    if (r.has(key)) ignored.push_back(key);
  r.alsoRead("diagnostic_period");
  r.finish();
  if (!ignored.empty()) {
    std::string w;
    for (const std::string& k : ignored) w += (w.empty() ? "" : ", ") + k;
    ROS_WARN_STREAM("navsat_transform: robot_localization features not implemented here, ignored: " << w);
  }
  return s;
}

class NavsatTransformNode {
 public:
  NavsatTransformNode(ros::NodeHandle& nh, ros::NodeHandle& pnh)
      : s_(readSettings(pnh)), transform_(s_.options), updater_(nh, pnh), tf_listener_(tf_buffer_) {
    monitor_.setStart(ros::Time::now().toSec());
    monitor_.addInput(kGps, s_.gps_timeout, true);
    if (!s_.datum.empty()) {
      const std::string e = transform_.setDatum(s_.datum[0], s_.datum[1], 0.0, s_.datum[2]);
      if (!e.empty()) throw thorvald_common::ParamError("navsat_transform: ~datum: " + e);
      announceDatum("the ~datum parameter");
    }
    gps_pub_ = nh.advertise<nav_msgs::Odometry>("odometry/gps", 10);
    if (s_.publish_filtered_gps) filtered_pub_ = nh.advertise<sensor_msgs::NavSatFix>("gps/filtered", 10);
    fix_sub_ = nh.subscribe("gps/fix", 10, &NavsatTransformNode::onFix, this);
    imu_sub_ = nh.subscribe("imu/data", 10, &NavsatTransformNode::onImu, this);
    odom_sub_ = nh.subscribe("odometry/filtered", 10, &NavsatTransformNode::onOdom, this);
    updater_.setHardwareID("navsat_transform");
    updater_.add("gnss", this, &NavsatTransformNode::diagnose);
    timer_ = nh.createTimer(ros::Duration(1.0), [this](const ros::TimerEvent&) { updater_.update(); });
  }

 private:
  void onImu(const sensor_msgs::ImuConstPtr& m) {
    const Eigen::Quaterniond q = toImuSample(*m).orientation;
    imu_yaw_ = rollPitchYaw(q).z();
    // base_link's roll and pitch (gravity's, the same in any world frame): the IMU's orientation less its mount.
    const std::optional<Eigen::Quaterniond> mount = mountOf(m->header.frame_id);
    if (mount) imu_tilt_ = rollPitchYaw(q * mount->conjugate()).head<2>();
  }

  /// The pose of a sensor frame in base_link from tf, looked up until found (the mounts are static).
  std::optional<Eigen::Isometry3d> sensorInBase(const std::string& frame) {
    if (frame.empty() || frame == s_.base_link_frame) return Eigen::Isometry3d::Identity();
    const auto known = mounts_.find(frame);
    if (known != mounts_.end()) return known->second;
    try {
      const Eigen::Isometry3d m =
          toIsometry(tf_buffer_.lookupTransform(s_.base_link_frame, frame, ros::Time(0)).transform);
      mounts_[frame] = m;
      return m;
    } catch (const tf2::TransformException& e) {
      no_mount_ = "no transform from '" + frame + "' to '" + s_.base_link_frame + "': " + e.what();
      return std::nullopt;
    }
  }
  std::optional<Eigen::Quaterniond> mountOf(const std::string& frame) {
    const std::optional<Eigen::Isometry3d> m = sensorInBase(frame);
    if (!m) return std::nullopt;
    return Eigen::Quaterniond(m->linear());
  }

  /// base_link's orientation in the world frame now: the world yaw from odometry/filtered (0 before it, as the
  /// datum takes it), roll and pitch from the IMU (odometry/filtered's when no IMU has come: 0 in two_d_mode).
  Eigen::Quaterniond baseInWorld() const {
    const double yaw = robot_ ? robot_->yaw : 0.0;
    const Eigen::Vector2d tilt = imu_tilt_ ? *imu_tilt_ : robot_tilt_;
    return fromRollPitchYaw(tilt.x(), tilt.y(), yaw);
  }

  void onOdom(const nav_msgs::OdometryConstPtr& m) {
    const PoseSample p = toPoseSample(m->pose);
    const Eigen::Vector3d rpy = rollPitchYaw(p.orientation);
    robot_ = WorldPose{p.position.x(), p.position.y(), p.position.z(), rpy.z()};
    robot_tilt_ = rpy.head<2>();
    if (!m->header.frame_id.empty()) s_.world_frame = m->header.frame_id;
    if (!m->child_frame_id.empty()) s_.base_link_frame = m->child_frame_id;
    if (s_.publish_filtered_gps && transform_.ready()) {
      const std::optional<LatLon> ll = transform_.toLatLon(p.position.x(), p.position.y());
      if (!ll) return;
      sensor_msgs::NavSatFix f;
      f.header = m->header;
      f.latitude = ll->lat_deg;
      f.longitude = ll->lon_deg;
      f.status.status = sensor_msgs::NavSatStatus::STATUS_FIX;
      filtered_pub_.publish(f);
    }
  }

  void onFix(const sensor_msgs::NavSatFixConstPtr& m) {
    const double now = ros::Time::now().toSec();
    if (m->status.status < sensor_msgs::NavSatStatus::STATUS_FIX || !std::isfinite(m->latitude) ||
        !std::isfinite(m->longitude)) {
      monitor_.received(kGps, now, false, "the receiver reports no fix");
      return;
    }
    monitor_.received(kGps, now);
    GeoFix fix;
    fix.lat_deg = m->latitude;
    fix.lon_deg = m->longitude;
    fix.alt_m = std::isfinite(m->altitude) ? m->altitude : 0.0;
    for (int i = 0; i < 9; ++i) fix.covariance_enu(i / 3, i % 3) = m->position_covariance[static_cast<std::size_t>(i)];
    // The fix is the antenna's (its frame_id): without the mount it cannot be moved to base_link.
    const std::optional<Eigen::Isometry3d> antenna = sensorInBase(m->header.frame_id);
    if (!antenna) {
      monitor_.refused(kGps, no_mount_);
      ROS_WARN_STREAM_THROTTLE(5.0, "navsat_transform: fix refused: " << no_mount_);
      return;
    }
    const Eigen::Vector3d offset = antennaOffsetInWorld(antenna->translation(), baseInWorld());
    if (!transform_.ready()) {
      GeoFix for_datum = fix;
      if (m->position_covariance_type == sensor_msgs::NavSatFix::COVARIANCE_TYPE_UNKNOWN)
        for_datum.covariance_enu.setConstant(std::numeric_limits<double>::quiet_NaN());
      if (!datumFromFix(for_datum, offset)) return;
    }
    const std::optional<WorldFix> w = transform_.toWorld(fix, offset);
    if (!w) {
      monitor_.refused(kGps, "fix outside UTM's latitudes");
      return;
    }
    monitor_.fused(kGps);
    nav_msgs::Odometry out;
    out.header.stamp = m->header.stamp.isZero() ? ros::Time::now() : m->header.stamp;
    out.header.frame_id = s_.world_frame;
    out.child_frame_id = s_.base_link_frame;
    out.pose.pose.position.x = w->position.x();
    out.pose.pose.position.y = w->position.y();
    out.pose.pose.position.z = w->position.z();
    out.pose.pose.orientation.w = 1.0;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) out.pose.covariance[static_cast<std::size_t>(i * 6 + j)] = w->covariance(i, j);
    for (int k = 3; k < 6; ++k) out.pose.covariance[static_cast<std::size_t>(k * 7)] = 1e6;  // no orientation
    gps_pub_.publish(out);
  }

  bool datumFromFix(const GeoFix& fix, const Eigen::Vector3d& antenna_offset) {
    const std::string refusal = datumFixRefusal(fix, s_.datum_max_sigma_m);
    if (!refusal.empty()) {
      waiting_ = "waiting for a fix good enough for the datum: " + refusal;
      ROS_INFO_STREAM_THROTTLE(5.0, "navsat_transform: " << waiting_);
      return false;
    }
    std::optional<double> yaw = s_.use_odometry_yaw && robot_ ? std::optional<double>(robot_->yaw) : imu_yaw_;
    if (!yaw) {
      waiting_ = s_.use_odometry_yaw ? "waiting for odometry/filtered for the heading at the datum"
                                     : "waiting for imu/data for the heading at the datum";
      return false;
    }
    const std::string e = transform_.setFromFix(fix, *yaw, robot_.value_or(WorldPose{}), antenna_offset);
    if (!e.empty()) {
      waiting_ = e;
      return false;
    }
    waiting_.clear();
    std::ostringstream from;
    from.precision(3);
    from << "the first fix with a horizontal sigma within " << s_.datum_max_sigma_m << " m (" << horizontalSigma(fix)
         << " m), the antenna " << antenna_offset.transpose() << " m from base_link";
    announceDatum(from.str());
    return true;
  }

  void announceDatum(const std::string& from) {
    const UtmPoint& u = transform_.datumUtm();
    ROS_INFO_STREAM("navsat_transform: datum from " << from << ": UTM zone " << u.zone << u.band << " E " << std::fixed
                                                    << u.easting << " N " << u.northing);
    if (!s_.broadcast_utm) return;
    const std::optional<WorldPose> g = transform_.utmInWorld();
    geometry_msgs::TransformStamped t;
    t.header.stamp = ros::Time::now();
    t.header.frame_id = s_.world_frame;
    t.child_frame_id = "utm";
    t.transform.translation.x = g->x;
    t.transform.translation.y = g->y;
    t.transform.translation.z = g->z;
    t.transform.rotation.z = std::sin(0.5 * g->yaw);
    t.transform.rotation.w = std::cos(0.5 * g->yaw);
    if (s_.utm_as_parent) {  // utm -> world: the inverse
      geometry_msgs::TransformStamped utm_root;
      utm_root.header = t.header;
      utm_root.header.frame_id = "utm";
      utm_root.transform.rotation.w = 1.0;
      t = composeMapToOdom(utm_root, t, s_.world_frame);
    }
    static_tf_.sendTransform(t);
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& st) {
    FusionHealth h = monitor_.evaluate(ros::Time::now().toSec());
    if (!transform_.ready() && h.level == FusionHealth::kOk) {
      h.level = FusionHealth::kWarn;
      h.reasons.push_back(waiting_.empty() ? "waiting for the first fix for the datum" : waiting_);
    }
    st.summary(static_cast<unsigned char>(h.level), h.summary());
    st.add("datum set", transform_.ready());
    st.add("datum_max_sigma_m", s_.datum_max_sigma_m);
    if (transform_.ready()) st.add("UTM zone", std::to_string(transform_.datumUtm().zone) + transform_.datumUtm().band);
  }

  NavsatSettings s_;
  NavsatTransform transform_;
  FusionMonitor monitor_;
  diagnostic_updater::Updater updater_;
  tf2_ros::StaticTransformBroadcaster static_tf_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  std::map<std::string, Eigen::Isometry3d> mounts_;  // sensor frames in base_link
  std::string no_mount_;
  ros::Publisher gps_pub_, filtered_pub_;
  ros::Subscriber fix_sub_, imu_sub_, odom_sub_;
  ros::Timer timer_;
  std::optional<double> imu_yaw_;
  std::optional<Eigen::Vector2d> imu_tilt_;  // base_link's roll, pitch from the IMU
  Eigen::Vector2d robot_tilt_ = Eigen::Vector2d::Zero();
  std::optional<WorldPose> robot_;
  std::string waiting_;
};

}  // namespace
}  // namespace thorvald_navigation

int main(int argc, char** argv) {
  return thorvald_common::runNode<thorvald_navigation::NavsatTransformNode>(argc, argv, "navsat_transform");
}
