// manipulator: drives the two stepper axes of the Cartesian arm through the manipulation
// controller's serial port (4-byte frames). Targets in metres (horizontal extension, distance of
// the end effector from the camera) become absolute step positions by the calibration (eq. 7 for
// the vertical axis, belt kinematics for the horizontal one), clamped to the axis limits.
#include <cmath>
#include <mutex>
#include <optional>

#include <diagnostic_updater/diagnostic_updater.h>
#include <geometry_msgs/PointStamped.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <std_msgs/Bool.h>

#include "cotton_harvester/control/manipulator_protocol.h"
#include "cotton_harvester/control/serial_port.h"
#include "../ros/calibration_params.h"
#include "../ros/node_params.h"

namespace cotton_harvester {
namespace control {
namespace {

/// What the node knows and wants of one axis.
struct AxisState {
  std::optional<std::int32_t> position;  ///< last reported step position
  std::optional<std::int32_t> target;    ///< wanted step position
  bool moving = false;                   ///< controller says it moves
  bool awaiting = false;                 ///< a move was sent, its end not reported yet
  ros::WallTime sent;
  int limit_hits = 0;
};

class ManipulatorNode {
 public:
  ManipulatorNode(ros::NodeHandle& nh, ros::NodeHandle& pnh, const NodeParams& params) : updater_(nh, pnh) {
    port_path_ = readString(params, "port", "/dev/ttyUSB0");
    baud_ = readInt(params, "baud", 115200, 1);
    reconnect_period_s_ = readPositive(params, "reconnect_period_s", 1.0);
    report_timeout_s_ = readPositive(params, "report_timeout_s", 1.0);
    calibration_ = loadCalibration(params.sub("calibration"));

    joints_pub_ = nh.advertise<sensor_msgs::JointState>("manipulator/joint_states", 10);
    busy_pub_ = nh.advertise<std_msgs::Bool>("manipulator/busy", 10);
    target_sub_ = nh.subscribe("manipulator/target", 10, &ManipulatorNode::onTarget, this);
    brush_sub_ = nh.subscribe("manipulator/brush", 10, &ManipulatorNode::onBrush, this);
    updater_.setHardwareID("manipulation controller " + port_path_);
    updater_.add("manipulator", this, &ManipulatorNode::diagnose);
    timer_ = nh.createWallTimer(ros::WallDuration(0.01), [this](const ros::WallTimerEvent&) { tick(); });
    publish_timer_ = nh.createWallTimer(ros::WallDuration(readPositive(params, "publish_period_s", 0.05)),
                                        [this](const ros::WallTimerEvent&) { publish(); });
  }

 private:
  AxisState& axis(Axis which) { return which == Axis::kHorizontal ? horizontal_ : vertical_; }

  void onTarget(const geometry_msgs::PointStamped::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    bool clamped = false;
    if (std::isfinite(msg->point.x)) {
      bool c = false;
      horizontal_.target = calibration_.targetSteps(Axis::kHorizontal, msg->point.x, &c);
      clamped |= c;
    }
    if (std::isfinite(msg->point.z)) {
      bool c = false;
      vertical_.target = calibration_.targetSteps(Axis::kVertical, msg->point.z, &c);
      clamped |= c;
    }
    if (clamped) {
      ++clamped_targets_;
      ROS_WARN_THROTTLE(1.0, "manipulator target (%.3f, %.3f) outside the axis limits: clamped", msg->point.x,
                        msg->point.z);
    }
  }

  void onBrush(const std_msgs::Bool::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    ManipulatorCommand command;
    command.kind = ManipulatorCommand::Kind::kBrush;
    command.brush_on = msg->data;
    send(command);
  }

  bool send(const ManipulatorCommand& command) {
    if (!port_.isOpen()) return false;
    const auto frame = encodeCommand(command);
    if (!port_.write(frame.data(), frame.size())) {
      ROS_ERROR("manipulation controller: %s", port_.lastError().c_str());
      return false;
    }
    ++frames_sent_;
    return true;
  }

  void tick() {
    std::lock_guard<std::mutex> lock(mutex_);
    const ros::WallTime now = ros::WallTime::now();
    if (!port_.isOpen()) {
      if ((now - last_attempt_).toSec() < reconnect_period_s_) return;
      last_attempt_ = now;
      if (!port_.open(port_path_, baud_)) {
        ROS_WARN_THROTTLE(5.0, "manipulation controller: %s", port_.lastError().c_str());
        return;
      }
      ROS_INFO("manipulation controller connected on %s", port_path_.c_str());
      horizontal_.awaiting = vertical_.awaiting = false;
      send(ManipulatorCommand{});  // query both axes
      last_report_ = now;
    }
    std::uint8_t buffer[256];
    const long n = port_.read(buffer, sizeof(buffer), 0);
    if (n < 0) {
      ROS_ERROR("manipulation controller lost: %s", port_.lastError().c_str());
      return;
    }
    for (const auto& frame : parser_.push(buffer, static_cast<std::size_t>(n))) {
      ManipulatorReport report;
      if (!decodeReport(frame, &report)) continue;
      last_report_ = now;
      if (report.target == ManipulatorReport::Target::kBrush) {
        brush_on_ = report.brush_on;
        continue;
      }
      AxisState& a =
          axis(report.target == ManipulatorReport::Target::kHorizontal ? Axis::kHorizontal : Axis::kVertical);
      a.position = report.position_steps;
      a.moving = report.moving;
      if (!report.moving) a.awaiting = false;
      if (report.limit && !report.moving) {
        // The axis stopped at its end stop short of the target: the move ends there (sending it again would only
        // hit the stop again and keep the arm busy for ever).
        ++a.limit_hits;
        if (a.target && a.position && *a.target != *a.position) {
          ROS_WARN("manipulator: %s axis at its end stop (%d steps) short of the target (%d steps): target dropped",
                   report.target == ManipulatorReport::Target::kHorizontal ? "horizontal" : "vertical", *a.position,
                   *a.target);
          a.target = a.position;
        }
      }
    }
    for (Axis which : {Axis::kHorizontal, Axis::kVertical}) {
      AxisState& a = axis(which);
      if (a.awaiting && (now - a.sent).toSec() > report_timeout_s_) {
        a.awaiting = false;  // no end report: ask where it is
        ++report_timeouts_;
        send(ManipulatorCommand{});
      }
      if (!a.position || !a.target || a.awaiting || a.moving || *a.position == *a.target) continue;
      ManipulatorCommand command;
      command.kind = ManipulatorCommand::Kind::kMove;
      command.move = ManipulatorCalibration::moveBetween(which, *a.position, *a.target);
      if (send(command)) {
        a.awaiting = true;
        a.sent = now;
      }
    }
  }

  void publish() {
    std::lock_guard<std::mutex> lock(mutex_);
    updater_.update();
    if (!horizontal_.position || !vertical_.position) return;
    sensor_msgs::JointState joints;
    joints.header.stamp = ros::Time::now();
    joints.name = {"horizontal", "vertical"};
    joints.position = {calibration_.horizontalExtensionFromSteps(*horizontal_.position),
                       calibration_.verticalDistanceFromSteps(*vertical_.position)};
    joints_pub_.publish(joints);
    std_msgs::Bool busy;
    for (const AxisState* a : {&horizontal_, &vertical_}) {
      busy.data |= a->moving || a->awaiting || (a->target && a->position && *a->target != *a->position);
    }
    busy.data |= !port_.isOpen();
    busy_pub_.publish(busy);
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& status) {
    if (!port_.isOpen()) {
      status.summary(diagnostic_msgs::DiagnosticStatus::ERROR, "no serial link: " + port_.lastError());
    } else if ((ros::WallTime::now() - last_report_).toSec() > 5.0 && (horizontal_.awaiting || vertical_.awaiting)) {
      status.summary(diagnostic_msgs::DiagnosticStatus::WARN, "controller does not report");
    } else {
      status.summary(diagnostic_msgs::DiagnosticStatus::OK, "connected");
    }
    status.add("port", port_path_);
    status.add("frames sent", frames_sent_);
    status.add("bytes rejected", parser_.rejectedBytes());
    status.add("targets clamped to limits", clamped_targets_);
    status.add("report timeouts", report_timeouts_);
    status.add("horizontal limit hits", horizontal_.limit_hits);
    status.add("vertical limit hits", vertical_.limit_hits);
    status.add("brush", brush_on_ ? "on" : "off");
  }

  std::string port_path_;
  int baud_ = 115200;
  double reconnect_period_s_ = 1.0, report_timeout_s_ = 1.0;
  ManipulatorCalibration calibration_;
  SerialPort port_;
  ManipulatorFrameParser parser_{0xB0};
  AxisState horizontal_, vertical_;
  bool brush_on_ = false;
  std::size_t frames_sent_ = 0, clamped_targets_ = 0, report_timeouts_ = 0;
  ros::WallTime last_attempt_, last_report_;
  std::mutex mutex_;
  diagnostic_updater::Updater updater_;
  ros::Publisher joints_pub_, busy_pub_;
  ros::Subscriber target_sub_, brush_sub_;
  ros::WallTimer timer_, publish_timer_;
};

}  // namespace
}  // namespace control
}  // namespace cotton_harvester

int main(int argc, char** argv) {
  ros::init(argc, argv, "manipulator");
  ros::NodeHandle nh, pnh("~");
  try {
    thorvald_common::ParamReader reader(pnh);
    reader.alsoRead("diagnostic_period");  // diagnostic_updater's own
    cotton_harvester::control::ManipulatorNode node(nh, pnh, cotton_harvester::control::NodeParams(reader));
    reader.finish();
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("manipulator cannot start: %s", e.what());
    return 1;
  }
  return 0;
}
