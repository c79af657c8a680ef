// Latency from an input message to the multiplexer's output on loopback, with 5 inputs at 100 Hz each, and the
// same through joy_teleop -> twist_mux. Needs a running roscore; starts twist_mux and joy_teleop itself (rosrun)
// in a private namespace and stops them at the end.
//   rosrun thorvald_twist_mux mux_latency_bench [--seconds S (per path, default 10)]
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>
#include <thorvald_common/bench_statistics.h>
#include <thorvald_common/command_line.h>
#include <geometry_msgs/Twist.h>
#include <ros/ros.h>
#include <sensor_msgs/Joy.h>

extern char** environ;

namespace {

using Clock = std::chrono::steady_clock;

constexpr int kInputs = 5;
constexpr double kRateHz = 100.0;
constexpr int kSeqModulo = 10000;  // the teleop path carries the sequence in a float32 axis: seq * 1e-4

/// A child process started with rosrun, interrupted and reaped on destruction.
class Child {
 public:
  explicit Child(const std::vector<std::string>& args) {
    std::vector<char*> argv;
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
    if (posix_spawnp(&pid_, argv[0], &actions, nullptr, argv.data(), environ) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&actions);
  }
  ~Child() {
    if (pid_ <= 0) return;
    kill(pid_, SIGINT);
    int status = 0;
    waitpid(pid_, &status, 0);
  }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;
  bool started() const { return pid_ > 0; }

 private:
  pid_t pid_ = -1;
};

/// Send times per sequence number of the measured input and the latencies of what came out.
class LatencyLog {
 public:
  /// Records a send; `counted` sends (after the warm-up) are the ones whose latency is kept.
  void sent(int seq, Clock::time_point t, bool counted) {
    std::lock_guard<std::mutex> lock(mutex_);
    sent_[seq % kSeqModulo] = {t, counted};
  }
  void received(int seq, Clock::time_point t) {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto it = sent_.find(seq % kSeqModulo);
    if (it == sent_.end()) return;
    if (it->second.second) {
      latencies_ms_.push_back(std::chrono::duration<double, std::milli>(t - it->second.first).count());
    }
    sent_.erase(it);
    ++received_count_;
  }
  unsigned long receivedCount() {
    std::lock_guard<std::mutex> lock(mutex_);
    return received_count_;
  }
  std::vector<double> latencies() {
    std::lock_guard<std::mutex> lock(mutex_);
    return latencies_ms_;
  }

 private:
  std::mutex mutex_;
  std::map<int, std::pair<Clock::time_point, bool>> sent_;  // seq -> send time, counted
  std::vector<double> latencies_ms_;
  unsigned long received_count_ = 0;
};

using thorvald_common::percentile;

XmlRpc::XmlRpcValue muxTopics() {
  XmlRpc::XmlRpcValue topics;
  for (int i = 0; i < kInputs; ++i) {
    topics[i]["name"] = "in" + std::to_string(i);
    topics[i]["topic"] = "in" + std::to_string(i);
    topics[i]["timeout"] = 0.5;
    topics[i]["priority"] = 10 * (i + 1);  // in4 is the highest of these
  }
  topics[kInputs]["name"] = "teleop";
  topics[kInputs]["topic"] = "teleop_joy/cmd_vel";
  topics[kInputs]["timeout"] = 0.5;
  topics[kInputs]["priority"] = 100;
  return topics;
}

struct PhaseResult {
  std::vector<double> latencies_ms;
  unsigned long sent = 0;
  unsigned long received = 0;
};

/// Publishes on `twist_inputs` (indices into `pubs`) and, when `joy` is set, Joy messages, each at kRateHz with the
/// sources staggered over the period; the measured source is the last listed (the teleop Joy if any).
PhaseResult runPhase(std::vector<ros::Publisher>& pubs, const std::vector<int>& twist_inputs, ros::Publisher* joy,
                     LatencyLog& log, double seconds) {
  const auto period = std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / kRateHz));
  const int sources = static_cast<int>(twist_inputs.size()) + (joy != nullptr ? 1 : 0);
  const auto warmup_end = Clock::now() + std::chrono::seconds(1);
  const auto end = warmup_end + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
  auto tick = Clock::now();
  int seq = 0;
  bool recording = false;
  PhaseResult result;
  while (ros::ok() && tick < end) {
    // Measure once the warm-up is over and the path has delivered at least once (all connections up).
    if (!recording && tick >= warmup_end && log.receivedCount() > 0) recording = true;
    for (int s = 0; s < sources; ++s) {
      std::this_thread::sleep_until(tick + period * s / sources);
      const bool measured = s == sources - 1;
      const auto now = Clock::now();
      if (joy != nullptr && measured) {
        sensor_msgs::Joy j;
        j.axes = {0.0f, static_cast<float>((seq % kSeqModulo) * 1e-4)};
        j.buttons = {1};
        log.sent(seq, now, recording);
        joy->publish(j);
      } else {
        geometry_msgs::Twist t;
        t.linear.x = seq;
        t.linear.y = twist_inputs[static_cast<std::size_t>(s)];
        if (measured) log.sent(seq, now, recording);
        pubs[static_cast<std::size_t>(twist_inputs[static_cast<std::size_t>(s)])].publish(t);
      }
      if (measured && recording) ++result.sent;
    }
    ++seq;
    tick += period;
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // let the last messages arrive
  result.latencies_ms = log.latencies();
  result.received = result.latencies_ms.size();
  return result;
}

void printRow(const char* name, const PhaseResult& r) {
  std::printf("%-30s %8lu %8lu %8.3f %8.3f %8.3f %8.3f\n", name, r.sent, r.received, percentile(r.latencies_ms, 0.5),
              percentile(r.latencies_ms, 0.9), percentile(r.latencies_ms, 0.99), percentile(r.latencies_ms, 1.0));
}

bool waitFor(const std::function<bool()>& condition, double timeout_s) {
  const auto deadline =
      Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(timeout_s));
  while (Clock::now() < deadline) {
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "mux_latency_bench", ros::init_options::AnonymousName | ros::init_options::NoSigintHandler);
  double seconds = 10.0;
  CLI::App app(
      "Latency from an input message to twist_mux's output on loopback (5 inputs at 100 Hz), and through "
      "joy_teleop -> twist_mux. Needs a running roscore; starts twist_mux and joy_teleop itself.",
      "mux_latency_bench");
  app.add_option("--seconds", seconds, "measuring time per path [s], after 1 s of warm-up")
      ->check(CLI::Range(0.1, 3600.0))
      ->capture_default_str();
  if (const auto code = thorvald_common::parseCommandLine(app, argc, argv)) return *code;
  if (!ros::master::check()) {
    std::fprintf(stderr, "mux_latency_bench: no ROS master at %s; start roscore first\n",
                 ros::master::getURI().c_str());
    return 1;
  }
  const std::string ns = "/mux_latency_bench_" + std::to_string(getpid());
  ros::param::set(ns + "/twist_mux/topics", muxTopics());
  ros::param::set(ns + "/joy_teleop/enable_button", 0);
  ros::param::set(ns + "/joy_teleop/axis_linear", 1);
  ros::param::set(ns + "/joy_teleop/scale_linear", 1.0);
  ros::NodeHandle nh(ns);

  LatencyLog mux_log;
  LatencyLog teleop_log;
  LatencyLog* active_log = &mux_log;
  std::mutex active_mutex;
  ros::Subscriber out = nh.subscribe<geometry_msgs::Twist>(
      "cmd_vel_out", 100,
      [&](const geometry_msgs::Twist::ConstPtr& m) {
        const auto now = Clock::now();
        std::lock_guard<std::mutex> lock(active_mutex);
        if (active_log == &teleop_log) {
          teleop_log.received(static_cast<int>(std::lround(m->linear.x * 1e4)), now);
        } else if (static_cast<int>(m->linear.y) == kInputs - 1) {
          mux_log.received(static_cast<int>(m->linear.x), now);
        }
      },
      ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
  std::vector<ros::Publisher> pubs;
  for (int i = 0; i < kInputs; ++i) pubs.push_back(nh.advertise<geometry_msgs::Twist>("in" + std::to_string(i), 100));
  ros::Publisher joy = nh.advertise<sensor_msgs::Joy>("joy", 100);
  ros::AsyncSpinner spinner(1);
  spinner.start();

  Child mux({"rosrun", "thorvald_twist_mux", "twist_mux", "__name:=twist_mux", "__ns:=" + ns});
  Child teleop(
      {"rosrun", "thorvald_teleop", "joy_teleop", "__name:=joy_teleop", "__ns:=" + ns, "cmd_vel:=teleop_joy/cmd_vel"});
  if (!mux.started() || !teleop.started()) {
    std::fprintf(stderr, "mux_latency_bench: cannot start rosrun (is the workspace sourced?)\n");
    return 1;
  }
  const bool connected = waitFor(
      [&] {
        return out.getNumPublishers() > 0 && joy.getNumSubscribers() > 0 &&
               std::all_of(pubs.begin(), pubs.end(), [](const ros::Publisher& p) { return p.getNumSubscribers() > 0; });
      },
      30.0);
  if (!connected) {
    std::fprintf(stderr, "mux_latency_bench: twist_mux or joy_teleop did not connect within 30 s\n");
    ros::param::del(ns);
    return 1;
  }

  std::printf("measuring input -> twist_mux -> output for %.0f s ...\n", seconds + 1.0);
  std::fflush(stdout);
  const PhaseResult direct = runPhase(pubs, {0, 1, 2, 3, 4}, nullptr, mux_log, seconds);
  {
    std::lock_guard<std::mutex> lock(active_mutex);
    active_log = &teleop_log;
  }
  std::printf("measuring Joy -> joy_teleop -> twist_mux for %.0f s ...\n", seconds + 1.0);
  std::fflush(stdout);
  const PhaseResult through_teleop = runPhase(pubs, {0, 1, 2, 3}, &joy, teleop_log, seconds);
  ros::param::del(ns);

  std::printf("twist_mux latency on loopback: %d sources at %.0f Hz each, %.0f s per path after 1 s warm-up\n", kInputs,
              kRateHz, seconds);
  std::printf("%-30s %8s %8s %8s %8s %8s %8s\n", "path", "sent", "received", "p50_ms", "p90_ms", "p99_ms", "max_ms");
  printRow("input -> twist_mux -> output", direct);
  printRow("Joy -> joy_teleop -> twist_mux", through_teleop);
  std::printf(
      "RESULT {\"mux_p50_ms\": %.3f, \"mux_p99_ms\": %.3f, \"teleop_mux_p50_ms\": %.3f, \"teleop_mux_p99_ms\": %.3f}\n",
      percentile(direct.latencies_ms, 0.5), percentile(direct.latencies_ms, 0.99),
      percentile(through_teleop.latencies_ms, 0.5), percentile(through_teleop.latencies_ms, 0.99));
  spinner.stop();
  return 0;
}
