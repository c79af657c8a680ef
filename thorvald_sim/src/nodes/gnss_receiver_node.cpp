// Node `gnss_receiver`: the simulated RTK-GNSS receiver (gnss_model.h). It follows the robot's ground truth
// (`ground_truth/odom`, the world frame taken as east-north-up around a WGS84 datum), puts the antenna where the
// robot file's receiver sits, and publishes the receiver's NMEA sentences on `nmea_sentence` (std_msgs/String, one
// sentence each), which thorvald_gnss's nmea_tcp_feeder serves to gpsd:
//   gnss_receiver -> nmea_sentence -> nmea_tcp_feeder -> gpsd -> gpsd_client -> gps/fix
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <std_msgs/String.h>

#include "thorvald_common/ros/param_reader.h"
#include "thorvald_common/ros/run_node.h"
#include "thorvald_sim/gnss_model.h"
#include "thorvald_sim/nmea_sentences.h"

namespace thorvald_sim {
namespace {

struct ReceiverParams {
  GnssModelParams model;
  Eigen::Vector3d antenna_m{0.0, 0.0, 0.0};  ///< antenna in base_link [m]
};

ReceiverParams loadParams(const ros::NodeHandle& pnh) {
  using thorvald_common::ParamRange;
  thorvald_common::ParamReader params(pnh);
  ReceiverParams p;
  GnssModelParams& m = p.model;
  m.rate_hz = params.number("rate", m.rate_hz, ParamRange::aboveUpTo(0.0, 100.0), "Hz");
  const auto datum = params.numbers("datum", {m.datum_latitude_deg, m.datum_longitude_deg, m.datum_altitude_m},
                                    ParamRange::any(), "[latitude deg, longitude deg, height m]", 3, 3);
  m.datum_latitude_deg = datum[0], m.datum_longitude_deg = datum[1], m.datum_altitude_m = datum[2];
  const auto antenna =
      params.numbers("antenna", {0.0, 0.0, 0.0}, ParamRange::closed(-20.0, 20.0), "m in base_link", 3, 3);
  p.antenna_m = {antenna[0], antenna[1], antenna[2]};
  m.seed = static_cast<uint64_t>(params.integer("seed", 1, 0));
  const auto acquire = params.numbers("acquire_times", {m.single_acquire_s, m.float_acquire_s, m.fixed_acquire_s},
                                      ParamRange::closed(0.0, 600.0), "s: [single, float, fixed]", 3, 3);
  m.single_acquire_s = acquire[0], m.float_acquire_s = acquire[1], m.fixed_acquire_s = acquire[2];
  const auto outages = params.numbers("outages", {}, ParamRange::atLeast(0.0), "s: [start, end, start, end, ...]");
  if (outages.size() % 2 != 0) {
    throw thorvald_common::ParamError(params.node() + ": parameter ~outages: found " + std::to_string(outages.size()) +
                                      " numbers, expected pairs [start, end]");
  }
  for (size_t i = 0; i + 1 < outages.size(); i += 2) m.outages.push_back({outages[i], outages[i + 1]});
  const auto zones = params.numbers("zones", {}, ParamRange::any(), "[east m, north m, radius m, best state 0-2]");
  if (zones.size() % 4 != 0) {
    throw thorvald_common::ParamError(params.node() + ": parameter ~zones: found " + std::to_string(zones.size()) +
                                      " numbers, expected quadruples [east, north, radius, best state]");
  }
  for (size_t i = 0; i + 3 < zones.size(); i += 4) {
    const int state = static_cast<int>(zones[i + 3]);
    if (state < 0 || state > 2 || state != zones[i + 3]) {
      throw thorvald_common::ParamError(params.node() + ": parameter ~zones: best state " +
                                        std::to_string(zones[i + 3]) + ", expected 0 (no fix), 1 (single), 2 (float)");
    }
    m.zones.push_back({zones[i], zones[i + 1], zones[i + 2], static_cast<GnssFixState>(state)});
  }
  const auto problems = m.validate();
  if (!problems.empty()) throw thorvald_common::ParamError(params.node() + ": " + problems.front());
  params.finish();
  return p;
}

class GnssReceiverNode {
 public:
  GnssReceiverNode(ros::NodeHandle& nh, ros::NodeHandle& pnh) : params_(loadParams(pnh)), model_(params_.model) {
    pub_ = nh.advertise<std_msgs::String>("nmea_sentence", 50);
    sub_ = nh.subscribe("ground_truth/odom", 10, &GnssReceiverNode::onTruth, this);
  }

 private:
  void onTruth(const nav_msgs::Odometry& odom) {
    const auto& p = odom.pose.pose.position;
    const auto& q = odom.pose.pose.orientation;
    const Eigen::Quaterniond orientation(q.w, q.x, q.y, q.z);
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z) || orientation.norm() < 0.5) {
      ROS_WARN_THROTTLE(10.0, "gnss_receiver: rejected a ground truth pose that is not finite");
      return;
    }
    const double stamp_s = odom.header.stamp.toSec();
    if (!start_s_) start_s_ = stamp_s;
    const double t = stamp_s - *start_s_;
    if (last_t_ && t < *last_t_) {
      ROS_WARN("gnss_receiver: time went back (simulation restarted?); the receiver starts again");
      model_ = GnssModel(params_.model);
      start_s_ = stamp_s;
      last_t_.reset();
      return;
    }
    last_t_ = t;
    const Eigen::Vector3d antenna = Eigen::Vector3d(p.x, p.y, p.z) + orientation.normalized() * params_.antenna_m;
    const auto solution = model_.update(t, antenna);
    if (!solution) return;
    for (const std::string& sentence : epochSentences(*solution)) {
      std_msgs::String msg;
      msg.data = sentence.substr(0, sentence.size() - 2);  // without CR LF
      pub_.publish(msg);
    }
  }

  ReceiverParams params_;
  GnssModel model_;
  ros::Publisher pub_;
  ros::Subscriber sub_;
  std::optional<double> start_s_;
  std::optional<double> last_t_;
};

}  // namespace
}  // namespace thorvald_sim

int main(int argc, char** argv) {
  return thorvald_common::runNode<thorvald_sim::GnssReceiverNode>(argc, argv, "gnss_receiver");
}
