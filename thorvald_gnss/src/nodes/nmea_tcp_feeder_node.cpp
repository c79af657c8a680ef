// Node `nmea_tcp_feeder`: serves NMEA sentences over TCP, the way a receiver's "TCP server" output does, so that
// gpsd (`gpsd tcp://127.0.0.1:10110`) reads them: a recorded log replayed at the receiver's rate, and the sentences
// published on `nmea_sentence` (a simulated receiver). See README.md.
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/ros.h>
#include <std_msgs/String.h>

#include "thorvald_common/ros/param_reader.h"
#include "thorvald_common/ros/run_node.h"
#include "thorvald_gnss/nmea_line_server.h"
#include "thorvald_gnss/nmea_log.h"

namespace thorvald_gnss {
namespace {

constexpr size_t kMaxSentenceBytes = 1024;  // NMEA allows 82; a longer line is not a sentence

struct FeederParams {
  std::string address = "127.0.0.1";
  int port = 10110;
  std::string file;  ///< NMEA log to replay; empty: only the topic
  double rate_hz = 5.0;
  bool loop = false;
  bool wait_for_client = true;
};

FeederParams loadParams(const ros::NodeHandle& pnh) {
  using thorvald_common::ParamRange;
  thorvald_common::ParamReader params(pnh);
  FeederParams p;
  p.address = params.text("address", p.address);
  p.port = params.integer("port", p.port, 0, 65535);
  p.file = params.text("file", p.file);
  p.rate_hz = params.number("rate", p.rate_hz, ParamRange::aboveUpTo(0.0, 100.0), "Hz, epochs of the log");
  p.loop = params.flag("loop", p.loop);
  p.wait_for_client = params.flag("wait_for_client", p.wait_for_client);
  params.alsoRead("diagnostic_period");
  params.finish();
  return p;
}

std::vector<NmeaEpoch> loadLog(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error("parameter ~file: cannot open '" + file + "'");
  size_t rejected = 0;
  auto epochs = readNmeaEpochs(in, &rejected);
  if (epochs.empty()) throw std::runtime_error("parameter ~file: '" + file + "' holds no NMEA sentence");
  if (rejected > 0)
    ROS_WARN("nmea_tcp_feeder: %zu lines of %s are not NMEA sentences; skipped", rejected, file.c_str());
  return epochs;
}

class NmeaTcpFeeder {
 public:
  NmeaTcpFeeder(ros::NodeHandle& nh, ros::NodeHandle& pnh)
      : params_(loadParams(pnh)), server_(params_.address, params_.port), updater_(nh, pnh) {
    if (!params_.file.empty()) epochs_ = loadLog(params_.file);
    ROS_INFO("nmea_tcp_feeder: serving NMEA on %s:%d%s", params_.address.c_str(), server_.port(),
             params_.file.empty()
                 ? ""
                 : (" (" + std::to_string(epochs_.size()) + " epochs of " + params_.file + ")").c_str());
    sub_ = nh.subscribe("nmea_sentence", 50, &NmeaTcpFeeder::onSentence, this);
    poll_timer_ = nh.createWallTimer(ros::WallDuration(0.02), [this](const ros::WallTimerEvent&) {
      server_.poll();
      updater_.update();
    });
    if (!epochs_.empty()) {
      replay_timer_ = nh.createWallTimer(ros::WallDuration(1.0 / params_.rate_hz),
                                         [this](const ros::WallTimerEvent&) { replayNext(); });
    }
    updater_.setHardwareID("tcp://" + params_.address + ":" + std::to_string(server_.port()));
    updater_.add("NMEA server", this, &NmeaTcpFeeder::diagnose);
  }

 private:
  void replayNext() {
    server_.poll();
    if (params_.wait_for_client && server_.clients() == 0 && next_ == 0) return;  // nothing lost before gpsd
    if (next_ >= epochs_.size()) {
      if (!params_.loop) return;
      next_ = 0;
    }
    server_.send(epochs_[next_++].text);
    ++epochs_sent_;
  }

  void onSentence(const std_msgs::String& msg) {
    std::string text = msg.data;
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
    if (text.size() < 6 || text.size() > kMaxSentenceBytes || text[0] != '$' ||
        text.find_first_of("\r\n") != std::string::npos) {
      ++rejected_;
      ROS_WARN_THROTTLE(10.0, "nmea_tcp_feeder: rejected a message on nmea_sentence that is not one NMEA sentence");
      return;
    }
    server_.send(text + "\r\n");
    ++sentences_sent_;
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& s) {
    s.summary(server_.clients() > 0 ? diagnostic_msgs::DiagnosticStatus::OK : diagnostic_msgs::DiagnosticStatus::WARN,
              server_.clients() > 0 ? "serving" : "no client connected (is gpsd started with this source?)");
    s.add("clients", server_.clients());
    s.add("clients accepted", server_.accepted());
    s.add("clients dropped", server_.dropped());
    s.add("log epochs sent", epochs_sent_);
    s.add("topic sentences sent", sentences_sent_);
    s.add("rejected topic messages", rejected_);
  }

  FeederParams params_;
  NmeaLineServer server_;
  diagnostic_updater::Updater updater_;
  std::vector<NmeaEpoch> epochs_;
  size_t next_ = 0;
  ros::Subscriber sub_;
  ros::WallTimer poll_timer_;
  ros::WallTimer replay_timer_;
  unsigned long epochs_sent_ = 0;
  unsigned long sentences_sent_ = 0;
  unsigned long rejected_ = 0;
};

}  // namespace
}  // namespace thorvald_gnss

int main(int argc, char** argv) {
  return thorvald_common::runNode<thorvald_gnss::NmeaTcpFeeder>(argc, argv, "nmea_tcp_feeder");
}
