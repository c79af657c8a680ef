#include "io_boards_ros.h"

#include <cstdio>
#include <utility>

namespace thorvald_base {
namespace {
std::string hex(uint8_t v) {
  char buf[8];
  std::snprintf(buf, sizeof(buf), "0x%02X", v);
  return buf;
}

std_msgs::Bool boolMsg(bool value) {
  std_msgs::Bool msg;
  msg.data = value;
  return msg;
}
}  // namespace

IoBoardsRos::IoBoardsRos(ros::NodeHandle nh, std::vector<std::unique_ptr<IoBoard>> boards, double hold_s)
    : hold_s_(hold_s) {
  boards_.resize(boards.size());
  for (size_t b = 0; b < boards.size(); ++b) {
    Board& board = boards_[b];
    board.device = std::move(boards[b]);
    const std::string ns = "io/" + board.device->name() + "/";
    board.unknown_pub = nh.advertise<std_msgs::Bool>(ns + "state_unknown", 1, true);
    board.outputs.resize(static_cast<size_t>(board.device->outputCount()));
    for (int k = 0; k < board.device->outputCount(); ++k) {
      Output& out = board.outputs[static_cast<size_t>(k)];
      const std::string topic = ns + "out" + std::to_string(k);
      out.state_pub = nh.advertise<std_msgs::Bool>(topic + "/state", 1, true);
      // No Nagle: a lamp switched off must not wait for a delayed ACK.
      out.sub = nh.subscribe<std_msgs::Bool>(
          topic, 10, [this, b, k](const std_msgs::Bool::ConstPtr& msg) { onCommand(b, k, *msg); }, ros::VoidConstPtr(),
          ros::TransportHints().tcpNoDelay());
    }
  }
}

void IoBoardsRos::onCommand(size_t board, int output, const std_msgs::Bool& msg) {
  Board& b = boards_[board];
  b.outputs[static_cast<size_t>(output)].last_on = msg.data ? ros::Time::now() : ros::Time();
  b.device->command(output, msg.data);
}

void IoBoardsRos::cycle(const ros::Time& now) {
  for (auto& b : boards_) {
    b.device->update(now.toSec());
    for (size_t k = 0; k < b.outputs.size(); ++k) {
      Output& out = b.outputs[k];
      if (hold_s_ > 0.0 && !out.last_on.isZero() && (now - out.last_on).toSec() > hold_s_) {
        ROS_WARN_STREAM("base_driver: " << b.device->name() << " out" << k << " switched off: its 'on' command was "
                                        << "not repeated within ~io_command_hold (" << hold_s_ << " s)");
        out.last_on = ros::Time();
        b.device->command(static_cast<int>(k), false);
      }
    }
    const IoBoardStatus s = b.device->status();
    if (static_cast<int>(s.state_unknown) != b.unknown_published) {
      if (s.state_unknown) {
        ROS_ERROR_STREAM("base_driver: relay state unknown on " << b.device->name() << ": " << s.why);
      } else if (b.unknown_published == 1) {
        ROS_INFO_STREAM("base_driver: " << b.device->name() << " confirms its outputs again (" << hex(s.confirmed)
                                        << ")");
      }
      b.unknown_published = s.state_unknown ? 1 : 0;
      b.unknown_pub.publish(boolMsg(s.state_unknown));
    }
    if (s.state_unknown) continue;
    for (size_t k = 0; k < b.outputs.size(); ++k) {
      const int on = (s.confirmed >> k) & 1;
      if (on == b.outputs[k].published) continue;
      b.outputs[k].published = on;
      b.outputs[k].state_pub.publish(boolMsg(on != 0));
    }
  }
}

void IoBoardsRos::diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) const {
  using diagnostic_msgs::DiagnosticStatus;
  std::string doubtful;
  for (const auto& b : boards_) {
    const IoBoardStatus s = b.device->status();
    const std::string& n = b.device->name();
    stat.add(n + " answering", s.answering ? "yes" : "no");
    stat.add(n + " outputs commanded", hex(s.commanded));
    stat.add(n + " outputs confirmed", s.state_unknown ? "unknown" : hex(s.confirmed));
    stat.add(n + " last frame [s ago]", s.age_s);
    if (s.state_unknown) doubtful += (doubtful.empty() ? "" : "; ") + n + ": " + s.why;
  }
  if (doubtful.empty()) {
    stat.summary(DiagnosticStatus::OK, "relay states confirmed");
  } else {
    stat.summary(DiagnosticStatus::ERROR, "relay state unknown: " + doubtful);
  }
}

}  // namespace thorvald_base
