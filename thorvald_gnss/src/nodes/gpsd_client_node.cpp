// Node `gpsd_client`: reads gpsd through its client library and publishes sensor_msgs/NavSatFix on `gps/fix`, with
// the fix status of an RTK receiver and a covariance from the receiver's error statistics (see README.md). A gpsd
// that is not running or goes away is logged, reported on diagnostics and retried; the node never stops for it.
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <string>
#include <thread>

#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/ros.h>
#include <sensor_msgs/NavSatFix.h>

#include "thorvald_common/ros/param_reader.h"
#include "thorvald_common/ros/run_node.h"
#include "thorvald_gnss/fix_conversion.h"
#include "thorvald_gnss/gpsd_link.h"
#include "thorvald_gnss/gpsd_source.h"

namespace thorvald_gnss {
namespace {

struct GpsdClientParams {
  std::string host = "localhost";
  int port = 2947;
  std::string frame_id = "gps_link";
  GpsdLinkParams link;
  ModeSigmas sigmas;
};

ModeSigma readSigma(thorvald_common::ParamReader& params, const std::string& name, const ModeSigma& fallback) {
  const auto v = params.numbers(name, {fallback.horizontal_m, fallback.vertical_m},
                                thorvald_common::ParamRange::above(0.0), "m: [horizontal, vertical]", 2, 2);
  return {v[0], v[1]};
}

GpsdClientParams loadParams(const ros::NodeHandle& pnh) {
  using thorvald_common::ParamRange;
  thorvald_common::ParamReader params(pnh);
  GpsdClientParams p;
  p.host = params.text("host", p.host);
  p.port = params.integer("port", p.port, 1, 65535);
  p.frame_id = params.text("frame_id", p.frame_id);
  p.link.timeout_s = params.number("timeout", p.link.timeout_s, ParamRange::aboveUpTo(0.0, 3600.0), "s");
  p.link.retry_interval_s =
      params.number("retry_interval", p.link.retry_interval_s, ParamRange::aboveUpTo(0.0, 3600.0), "s");
  p.sigmas.rtk_fixed = readSigma(params, "sigma_rtk_fixed", p.sigmas.rtk_fixed);
  p.sigmas.rtk_float = readSigma(params, "sigma_rtk_float", p.sigmas.rtk_float);
  p.sigmas.dgps = readSigma(params, "sigma_dgps", p.sigmas.dgps);
  p.sigmas.single = readSigma(params, "sigma_single", p.sigmas.single);
  p.sigmas.gst_max_age_s = params.number("gst_max_age", p.sigmas.gst_max_age_s, ParamRange::closed(0.0, 60.0), "s");
  if (p.host.empty()) {
    throw thorvald_common::ParamError(params.node() + ": parameter ~host: found an empty string, expected a host name");
  }
  params.alsoRead("diagnostic_period");  // diagnostic_updater's
  params.finish();
  return p;
}

const char* gpsdStatusName(int status, bool has_fix) {
  if (!has_fix) return "no fix";
  switch (status) {
    case 2:
      return "DGPS fix";
    case 3:
      return "RTK fixed";
    case 4:
      return "RTK float";
    default:
      return "single fix";
  }
}

double monotonicNow() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// Owns the gpsd connection on a thread of its own (libgps blocks in gps_waiting) and publishes from it; the
/// diagnostics run on the spinner's thread. `link_` and the figures it reports are shared under `mutex_`.
class GpsdClientNode {
 public:
  GpsdClientNode(ros::NodeHandle& nh, ros::NodeHandle& pnh)
      : params_(loadParams(pnh)), converter_(params_.sigmas), link_(params_.link), updater_(nh, pnh) {
    pub_ = nh.advertise<sensor_msgs::NavSatFix>("gps/fix", 10);
    updater_.setHardwareID("gpsd " + params_.host + ":" + std::to_string(params_.port));
    updater_.add("gpsd", this, &GpsdClientNode::diagnose);
    diagnostics_timer_ =
        nh.createWallTimer(ros::WallDuration(0.1), [this](const ros::WallTimerEvent&) { updater_.update(); });
    worker_ = std::thread([this] { run(); });
  }

  ~GpsdClientNode() {
    stop_ = true;
    worker_.join();
  }

 private:
  void run() {
    GpsdSource source;
    while (!stop_ && ros::ok()) {
      const double now = monotonicNow();
      if (!source.isOpen()) {
        if (shouldConnect(now)) connect(source, now);
        std::this_thread::sleep_for(std::chrono::milliseconds(source.isOpen() ? 0 : 50));
        continue;
      }
      readOnce(source);
      std::lock_guard<std::mutex> lock(mutex_);
      if (link_.timedOut(monotonicNow())) {
        source.close();
        const std::string why = "no report from gpsd for " + std::to_string(params_.link.timeout_s) + " s";
        ROS_WARN("gpsd_client: %s; reconnecting", why.c_str());
        link_.disconnected(monotonicNow(), why);
      }
    }
  }

  bool shouldConnect(double now) {
    std::lock_guard<std::mutex> lock(mutex_);
    return link_.shouldConnect(now);
  }

  void connect(GpsdSource& source, double now) {
    std::string why;
    const bool ok = source.open(params_.host, std::to_string(params_.port), why);
    std::lock_guard<std::mutex> lock(mutex_);
    if (ok) {
      link_.connected(now);
      ROS_INFO("gpsd_client: connected to gpsd at %s:%d", params_.host.c_str(), params_.port);
    } else {
      link_.connectFailed(now, why);
      ROS_ERROR_THROTTLE(10.0, "gpsd_client: %s; retrying every %.1f s", why.c_str(), params_.link.retry_interval_s);
    }
  }

  void readOnce(GpsdSource& source) {
    GpsdFix fix;
    GpsdGst gst;
    std::string why;
    const auto result = source.read(0.1, fix, gst, why);
    std::lock_guard<std::mutex> lock(mutex_);
    if (result == GpsdSource::ReadResult::kError) {
      source.close();
      link_.disconnected(monotonicNow(), why);
      ROS_ERROR("gpsd_client: %s; reconnecting", why.c_str());
    } else if (result == GpsdSource::ReadResult::kGst) {
      if (!converter_.addGst(gst)) ++rejected_gst_;
    } else if (result == GpsdSource::ReadResult::kFix) {
      publish(fix);
    }
  }

  /// Publishes the first report of each epoch (gpsd reports an epoch again after each sentence); holds mutex_.
  void publish(const GpsdFix& fix) {
    const NavFix out = converter_.convert(fix);
    const bool has_fix = out.status != FixStatus::kNoFix;
    link_.report(monotonicNow(), has_fix, gpsdStatusName(fix.status, has_fix));
    if (out.repeat) return;
    sensor_msgs::NavSatFix msg;
    msg.header.stamp = ros::Time::now();
    msg.header.frame_id = params_.frame_id;
    msg.status.status = static_cast<int8_t>(out.status);
    msg.status.service = sensor_msgs::NavSatStatus::SERVICE_GPS;
    msg.latitude = out.latitude_deg;
    msg.longitude = out.longitude_deg;
    msg.altitude = out.altitude_m;
    for (size_t i = 0; i < 9; ++i) msg.position_covariance[i] = out.covariance[i];
    msg.position_covariance_type = static_cast<uint8_t>(out.covariance_type);
    pub_.publish(msg);
    ++published_;
    last_source_ = out.covariance_source;
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& s) {
    std::lock_guard<std::mutex> lock(mutex_);
    const LinkHealth health = link_.health(monotonicNow());
    s.summary(static_cast<unsigned char>(health.level), health.message);
    s.add("gpsd", params_.host + ":" + std::to_string(params_.port));
    s.add("connections", link_.connections());
    s.add("failed connection attempts", link_.failedAttempts());
    s.add("last error", link_.lastError());
    s.add("fix reports", link_.reports());
    s.add("reports with a fix", link_.fixes());
    s.add("messages published", published_);
    s.add("covariance from", covarianceSourceName(last_source_));
    s.add("rejected GST reports", rejected_gst_);
  }

  GpsdClientParams params_;
  std::mutex mutex_;
  FixConverter converter_;
  GpsdLink link_;
  diagnostic_updater::Updater updater_;
  ros::Publisher pub_;
  ros::WallTimer diagnostics_timer_;
  std::atomic<bool> stop_{false};
  std::thread worker_;
  unsigned long published_ = 0;
  unsigned long rejected_gst_ = 0;
  CovarianceSource last_source_ = CovarianceSource::kNone;
};

}  // namespace
}  // namespace thorvald_gnss

int main(int argc, char** argv) {
  return thorvald_common::runNode<thorvald_gnss::GpsdClientNode>(argc, argv, "gpsd_client");
}
