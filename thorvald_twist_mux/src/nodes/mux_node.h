#pragma once

#include <memory>
#include <string>
#include <vector>

#include <diagnostic_updater/diagnostic_updater.h>
#include <geometry_msgs/Twist.h>
#include <geometry_msgs/TwistStamped.h>
#include <ros/ros.h>
#include <std_msgs/Bool.h>
#include <thorvald_common/ros/param_reader.h>

#include "../ros/mux_params.h"
#include "thorvald_twist_mux/twist_selector.h"

namespace thorvald_twist_mux {

/// ROS shell of the multiplexer: subscribes the configured inputs and locks, publishes the winner's message on
/// `cmd_vel_out` from that input's callback, and owns the status, diagnostics, marker and the check timer.
/// All callbacks run on the one spinner thread, so the selector needs no lock.
class MuxNode {
 public:
  /// Reads and validates parameters through `params` (the caller finishes the reader); throws
  /// std::runtime_error (thorvald_common::ParamError for a mistyped option) with the reason when the node cannot start.
  MuxNode(ros::NodeHandle nh, ros::NodeHandle pnh, thorvald_common::ParamReader& params);

 private:
  struct InputCounters {
    unsigned long received = 0;
    unsigned long published = 0;
    unsigned long rejected = 0;  ///< non-finite components
  };

  void onInput(std::size_t index, const geometry_msgs::Twist& twist, const std_msgs::Header* header);
  void onLock(std::size_t index, const std_msgs::Bool& msg);
  void onCheck(const ros::TimerEvent& event);
  void publishOutput(const geometry_msgs::Twist& twist, const std_msgs::Header* header, bool stop);
  void handleLoss(double now_s);
  void refreshStatus(double now_s);
  void diagnoseInput(std::size_t index, diagnostic_updater::DiagnosticStatusWrapper& status);
  void diagnoseLock(std::size_t index, diagnostic_updater::DiagnosticStatusWrapper& status);

  ros::NodeHandle nh_;
  ros::NodeHandle pnh_;
  MuxOptions options_;
  std::unique_ptr<TwistSelector> selector_;
  std::vector<ros::Subscriber> subscribers_;
  std::vector<InputCounters> counters_;
  std::vector<unsigned long> lock_messages_;
  unsigned long stops_published_ = 0;
  ros::Publisher output_pub_;
  ros::Publisher active_pub_;
  ros::Publisher locks_pub_;
  ros::Publisher marker_pub_;
  std::string last_active_ = "?";
  std::string last_locks_ = "?";
  ros::Timer check_timer_;
  diagnostic_updater::Updater updater_;
};

}  // namespace thorvald_twist_mux
