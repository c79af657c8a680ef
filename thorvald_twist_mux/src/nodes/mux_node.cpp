#include "mux_node.h"

#include <cmath>
#include <stdexcept>

#include <std_msgs/String.h>
#include <visualization_msgs/Marker.h>

namespace thorvald_twist_mux {
namespace {

bool isFinite(const geometry_msgs::Twist& t) {
  return std::isfinite(t.linear.x) && std::isfinite(t.linear.y) && std::isfinite(t.linear.z) &&
         std::isfinite(t.angular.x) && std::isfinite(t.angular.y) && std::isfinite(t.angular.z);
}

MuxOptions readOptions(thorvald_common::ParamReader& params) {
  MuxOptions o;
  o.zero_on_loss = params.flag("zero_on_loss", o.zero_on_loss);
  o.use_stamped = params.flag("use_stamped", o.use_stamped);
  o.publish_marker = params.flag("publish_marker", o.publish_marker);
  o.frame_id = params.text("frame_id", o.frame_id);
  o.check_rate_hz =
      params.number("check_rate", o.check_rate_hz, thorvald_common::ParamRange::aboveUpTo(0.0, 1000.0), "Hz");
  const std::string error = validateMuxOptions(o);
  if (!error.empty()) throw thorvald_common::ParamError(params.node() + ": " + error);
  return o;
}

/// twist_mux's `topics` and `locks` lists, read raw (either of twist_mux's forms) and counted as read.
MuxConfig readConfig(thorvald_common::ParamReader& params, ros::NodeHandle& pnh, bool use_stamped) {
  MuxConfig config;
  XmlRpc::XmlRpcValue topics;
  if (!params.raw("topics", &topics)) {
    throw std::runtime_error("parameter " + pnh.resolveName("topics") +
                             " is missing, expected a list of {name, topic, timeout, priority}");
  }
  config.inputs = parseMuxEntries(topics, "topics", use_stamped);
  XmlRpc::XmlRpcValue locks;
  if (params.raw("locks", &locks)) config.locks = parseMuxEntries(locks, "locks", false);
  const std::string error = validateMuxConfig(config);
  if (!error.empty()) throw std::runtime_error(error);
  return config;
}

}  // namespace

MuxNode::MuxNode(ros::NodeHandle nh, ros::NodeHandle pnh, thorvald_common::ParamReader& params)
    : nh_(nh), pnh_(pnh), options_(readOptions(params)), updater_(nh_, pnh_) {
  selector_ = std::make_unique<TwistSelector>(readConfig(params, pnh_, options_.use_stamped));
  params.alsoRead("diagnostic_period");  // diagnostic_updater's
  const MuxConfig& config = selector_->config();
  counters_.resize(config.inputs.size());
  lock_messages_.resize(config.locks.size(), 0);

  if (options_.use_stamped) {
    output_pub_ = nh_.advertise<geometry_msgs::TwistStamped>("cmd_vel_out", 10);
  } else {
    output_pub_ = nh_.advertise<geometry_msgs::Twist>("cmd_vel_out", 10);
  }
  active_pub_ = pnh_.advertise<std_msgs::String>("active", 1, true);
  locks_pub_ = pnh_.advertise<std_msgs::String>("engaged_locks", 1, true);
  if (options_.publish_marker) marker_pub_ = pnh_.advertise<visualization_msgs::Marker>("marker", 1);

  const auto hints = ros::TransportHints().tcpNoDelay();
  for (std::size_t i = 0; i < config.inputs.size(); ++i) {
    const MuxEntry& e = config.inputs[i];
    if (e.stamped) {
      subscribers_.push_back(nh_.subscribe<geometry_msgs::TwistStamped>(
          e.topic, 10, [this, i](const geometry_msgs::TwistStamped::ConstPtr& m) { onInput(i, m->twist, &m->header); },
          ros::VoidConstPtr(), hints));
    } else {
      subscribers_.push_back(nh_.subscribe<geometry_msgs::Twist>(
          e.topic, 10, [this, i](const geometry_msgs::Twist::ConstPtr& m) { onInput(i, *m, nullptr); },
          ros::VoidConstPtr(), hints));
    }
    updater_.add("input " + e.name, [this, i](diagnostic_updater::DiagnosticStatusWrapper& s) { diagnoseInput(i, s); });
  }
  for (std::size_t i = 0; i < config.locks.size(); ++i) {
    subscribers_.push_back(nh_.subscribe<std_msgs::Bool>(
        config.locks[i].topic, 10, [this, i](const std_msgs::Bool::ConstPtr& m) { onLock(i, *m); }, ros::VoidConstPtr(),
        hints));
    updater_.add("lock " + config.locks[i].name,
                 [this, i](diagnostic_updater::DiagnosticStatusWrapper& s) { diagnoseLock(i, s); });
  }
  updater_.setHardwareID("none");
  refreshStatus(ros::Time::now().toSec());
  check_timer_ = nh_.createTimer(ros::Duration(1.0 / options_.check_rate_hz), &MuxNode::onCheck, this);
}

void MuxNode::onInput(std::size_t index, const geometry_msgs::Twist& twist, const std_msgs::Header* header) {
  InputCounters& c = counters_[index];
  ++c.received;
  if (!isFinite(twist)) {
    ++c.rejected;
    ROS_WARN_THROTTLE(1.0, "twist_mux: rejected a non-finite twist on input '%s'",
                      selector_->config().inputs[index].name.c_str());
    return;
  }
  const double now_s = ros::Time::now().toSec();
  if (selector_->acceptInput(index, now_s)) {
    ++c.published;
    publishOutput(twist, header, false);
  }
  refreshStatus(now_s);
}

void MuxNode::onLock(std::size_t index, const std_msgs::Bool& msg) {
  ++lock_messages_[index];
  const double now_s = ros::Time::now().toSec();
  selector_->acceptLock(index, msg.data, now_s);
  handleLoss(now_s);
  refreshStatus(now_s);
}

void MuxNode::onCheck(const ros::TimerEvent&) {
  const double now_s = ros::Time::now().toSec();
  handleLoss(now_s);
  refreshStatus(now_s);
  updater_.update();
}

void MuxNode::handleLoss(double now_s) {
  if (!selector_->takeDrivingLoss(now_s) || !options_.zero_on_loss) return;
  ++stops_published_;
  publishOutput(geometry_msgs::Twist(), nullptr, true);
}

void MuxNode::publishOutput(const geometry_msgs::Twist& twist, const std_msgs::Header* header, bool stop) {
  if (options_.use_stamped) {
    geometry_msgs::TwistStamped out;
    if (header != nullptr) {
      out.header = *header;
    } else {
      out.header.stamp = ros::Time::now();
      out.header.frame_id = options_.frame_id;
    }
    out.twist = twist;
    output_pub_.publish(out);
  } else {
    output_pub_.publish(twist);
  }
  if (!options_.publish_marker) return;
  visualization_msgs::Marker m;
  m.header.stamp = ros::Time::now();
  m.header.frame_id = options_.frame_id;
  m.ns = "cmd_vel_out";
  m.type = visualization_msgs::Marker::ARROW;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.points.resize(2);
  m.points[1].x = twist.linear.x;  // arrow tip at the commanded velocity [m/s] drawn as metres
  m.points[1].y = twist.linear.y;
  m.scale.x = 0.05;  // shaft diameter [m]
  m.scale.y = 0.1;   // head diameter [m]
  m.scale.z = 0.1;   // head length [m]
  m.color.a = 1.0;
  m.color.r = stop ? 1.0f : 0.1f;
  m.color.g = stop ? 0.1f : 0.9f;
  m.color.b = 0.1f;
  marker_pub_.publish(m);
}

void MuxNode::refreshStatus(double now_s) {
  const int active = selector_->activeInput(now_s);
  const std::string active_name = active == TwistSelector::kNone
                                      ? std::string()
                                      : selector_->config().inputs[static_cast<std::size_t>(active)].name;
  if (active_name != last_active_) {
    std_msgs::String msg;
    msg.data = active_name;
    active_pub_.publish(msg);
    last_active_ = active_name;
  }
  const std::string locks = engagedLockNames(*selector_, now_s);
  if (locks != last_locks_) {
    std_msgs::String msg;
    msg.data = locks;
    locks_pub_.publish(msg);
    last_locks_ = locks;
  }
}

void MuxNode::diagnoseInput(std::size_t index, diagnostic_updater::DiagnosticStatusWrapper& status) {
  const double now_s = ros::Time::now().toSec();
  const MuxEntry& e = selector_->config().inputs[index];
  const InputCounters& c = counters_[index];
  std::string state = "idle (never heard)";
  if (selector_->activeInput(now_s) == static_cast<int>(index)) {
    state = "active";
  } else if (selector_->inputHeard(index)) {
    if (selector_->inputExpired(index, now_s)) {
      state = "timed out";
    } else if (selector_->inputMasked(index, now_s)) {
      state = "masked by lock";
    } else {
      state = "outranked";
    }
  }
  if (c.rejected > 0) {
    status.summaryf(diagnostic_msgs::DiagnosticStatus::WARN, "%s; %lu non-finite twists rejected", state.c_str(),
                    c.rejected);
  } else {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, state);
  }
  status.add("topic", nh_.resolveName(e.topic));
  status.add("priority", e.priority);
  status.add("timeout [s]", e.timeout_s);
  status.add("age [s]", selector_->inputAge(index, now_s));
  status.add("received", c.received);
  status.add("published", c.published);
  status.add("rejected", c.rejected);
  status.add("stops published (all inputs)", stops_published_);
}

void MuxNode::diagnoseLock(std::size_t index, diagnostic_updater::DiagnosticStatusWrapper& status) {
  const double now_s = ros::Time::now().toSec();
  const MuxEntry& e = selector_->config().locks[index];
  if (!selector_->lockEngaged(index, now_s)) {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, "released");
  } else if (selector_->lockByWatchdog(index, now_s)) {
    status.summary(diagnostic_msgs::DiagnosticStatus::WARN, "engaged: watchdog (not heard within timeout)");
  } else {
    status.summary(diagnostic_msgs::DiagnosticStatus::WARN, "engaged: last message true");
  }
  status.add("topic", nh_.resolveName(e.topic));
  status.add("priority", e.priority);
  status.add("timeout [s]", e.timeout_s);
  status.add("age [s]", selector_->lockAge(index, now_s));
  status.add("messages", lock_messages_[index]);
}

}  // namespace thorvald_twist_mux
