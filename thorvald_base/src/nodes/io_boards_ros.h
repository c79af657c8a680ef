#pragma once

#include <diagnostic_updater/DiagnosticStatusWrapper.h>
#include <ros/ros.h>
#include <std_msgs/Bool.h>

#include <memory>
#include <string>
#include <vector>

#include "thorvald_base/io_board.h"

namespace thorvald_base {

/// base_driver's relay boards on ROS. Per board `ioN` of the robot file and output k (0..7): commands on
/// `io/ioN/outk` (std_msgs/Bool), the state the board confirmed on `io/ioN/outk/state` (latched, published on
/// change while the state is known), and `io/ioN/state_unknown` (latched Bool, true while the outputs' state is in
/// doubt: not yet confirmed, a command not echoed, the board silent). With `hold_s` > 0 an output commanded on is
/// switched off when its command is not repeated within hold_s: a relay follows a live source only.
class IoBoardsRos {
 public:
  IoBoardsRos(ros::NodeHandle nh, std::vector<std::unique_ptr<IoBoard>> boards, double hold_s);

  /// Once per control cycle after the hardware's poll: hold timeouts, state topics, log lines on a change of doubt.
  void cycle(const ros::Time& now);
  /// The "io boards" diagnostics: ERROR naming every board whose state is unknown.
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) const;
  bool empty() const { return boards_.empty(); }

 private:
  struct Output {
    ros::Subscriber sub;
    ros::Publisher state_pub;
    ros::Time last_on;  ///< last command `on` [ROS time]; zero when off
    int published = -1;
  };
  struct Board {
    std::unique_ptr<IoBoard> device;
    std::vector<Output> outputs;
    ros::Publisher unknown_pub;
    int unknown_published = -1;
  };
  void onCommand(size_t board, int output, const std_msgs::Bool& msg);

  std::vector<Board> boards_;
  double hold_s_;
};

}  // namespace thorvald_base
