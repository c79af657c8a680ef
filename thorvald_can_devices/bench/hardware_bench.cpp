// Hardware-mode figures, run inside launch/hardware_bench.launch (base_driver + can_device_sim, 9 drives):
//  - latency from a twist_mux/cmd_vel message to the last drive's command frame on the bus (p50, p99);
//  - frames per second the virtual bus carries between two processes;
//  - base_driver's CPU at 50 Hz with 9 drives (from /proc/<pid>/stat, pid asked from the node itself).
// When done it asks base_driver and can_device_sim to shut down and, when roslaunch started it, sends roslaunch the
// SIGINT of a Ctrl-C, so the launch ends by itself, cleanly (exit code 0, no "REQUIRED process has died").
//   roslaunch thorvald_can_devices hardware_bench.launch
//   (the node's options: --bus NAME --samples N --last-node N; --help lists them)
#include <geometry_msgs/Twist.h>
#include <ros/master.h>
#include <ros/network.h>
#include <ros/ros.h>
#include <signal.h>
#include <unistd.h>
#include <xmlrpcpp/XmlRpcClient.h>

#include <CLI/CLI.hpp>
#include <thorvald_common/bench_statistics.h>
#include <thorvald_common/command_line.h>
#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

#include "bus_throughput.h"
#include "thorvald_can_devices/drive_scaling.h"
#include "thorvald_can_devices/thorvald_drive_protocol.h"
#include "thorvald_can_devices/virtual_can_bus.h"

using namespace thorvald_can_devices;

namespace {

/// Calls `method` (getPid, shutdown) of a node's XML-RPC API; false when the node or the call failed.
bool callNode(const std::string& node, const std::string& method, const std::string& argument,
              XmlRpc::XmlRpcValue* reply) {
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  args[1] = node;
  if (!ros::master::execute("lookupNode", args, result, payload, false)) return false;
  std::string uri = static_cast<std::string>(payload);
  std::string host;
  uint32_t port = 0;
  if (!ros::network::splitURI(uri, host, port)) return false;
  XmlRpc::XmlRpcClient client(host.c_str(), port, "/");
  XmlRpc::XmlRpcValue a;
  a[0] = ros::this_node::getName();
  if (!argument.empty()) a[1] = argument;
  return client.execute(method.c_str(), a, *reply) && reply->size() >= 3;
}

int nodePid(const std::string& node) {
  XmlRpc::XmlRpcValue r;
  return callNode(node, "getPid", "", &r) ? static_cast<int>(r[2]) : -1;
}

double cpuSeconds(int pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  std::getline(in, line);
  std::istringstream s(line.substr(line.rfind(')') + 2));
  std::string field;
  double utime = 0, stime = 0;
  for (int i = 3; i <= 15 && s >> field; ++i) {
    if (i == 14) utime = std::stod(field);
    if (i == 15) stime = std::stod(field);
  }
  return (utime + stime) / static_cast<double>(::sysconf(_SC_CLK_TCK));
}

using thorvald_common::percentile;

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "hardware_bench");
  std::vector<std::string> args;
  ros::removeROSArgs(argc, argv, args);
  CLI::App app{
      "hardware_bench: cmd_vel -> CAN frame latency, bus throughput and base_driver's CPU (run it through "
      "hardware_bench.launch)"};
  std::string bus_name = "bench";
  int samples = 200, last_node = 9;
  app.add_option("--bus", bus_name, "virtual bus base_driver and can_device_sim use");
  app.add_option("--samples", samples, "latency samples")->check(CLI::Range(1, 100000));
  app.add_option("--last-node", last_node, "node id of the drive whose command frame ends a sample")
      ->check(CLI::Range(1, 127));
  app.name("hardware_bench");
  if (const auto code = thorvald_common::parseCommandLine(app, {args.begin() + 1, args.end()})) return *code;
  ros::NodeHandle nh;
  VirtualCanBus spy(bus_name);
  auto pub = nh.advertise<geometry_msgs::Twist>("twist_mux/cmd_vel", 1);
  const ros::WallTime wait_end = ros::WallTime::now() + ros::WallDuration(30.0);
  while (ros::ok() && pub.getNumSubscribers() == 0 && ros::WallTime::now() < wait_end) ros::WallDuration(0.05).sleep();
  const int pid = nodePid(ros::this_node::getNamespace() + "/base_driver");
  if (pid <= 0) {
    std::fprintf(stderr, "hardware_bench: cannot find base_driver's pid\n");
    return 1;
  }
  ros::WallDuration(1.0).sleep();  // let the drives come up after start-up

  // Latency: each sample commands a new speed and waits for the last drive's RPDO1 with the matching value.
  thorvald_base::DriveConfig d;
  d.r_wheel = 0.2;
  d.prp_gr_rt = 42;
  d.prp_max_rpm = 3000;
  std::vector<double> latency_ms;
  const double cpu0 = cpuSeconds(pid);
  const ros::WallTime t_cpu0 = ros::WallTime::now();
  for (int i = 0; i < samples && ros::ok(); ++i) {
    const double vx = 0.1 + 0.002 * (i % 100);
    const int32_t expected = ThorvaldScaling::propulsionCommand(vx / d.r_wheel, d);
    geometry_msgs::Twist t;
    t.linear.x = vx;
    CanFrame f;
    while (spy.receive(&f)) {
    }
    const ros::WallTime sent = ros::WallTime::now();
    pub.publish(t);
    bool seen = false;
    while (!seen && ros::WallTime::now() - sent < ros::WallDuration(0.5)) {
      if (!spy.receive(&f)) {
        spy.waitReadable(0.001);
        continue;
      }
      if (f.stdId() == thorvald_ids::kCommand + static_cast<uint32_t>(last_node) && getI32(f, 4) == expected)
        seen = true;
    }
    if (seen) latency_ms.push_back((ros::WallTime::now() - sent).toSec() * 1000.0);
    ros::WallDuration(0.013 + 0.007 * (i % 3)).sleep();  // spread the commands over the 20 ms cycle
  }
  const double cpu_pct = 100.0 * (cpuSeconds(pid) - cpu0) / (ros::WallTime::now() - t_cpu0).toSec();
  const auto bus = measureThroughput(100000);

  std::printf("%-40s %12s\n", "figure", "value");
  std::printf("%-40s %12zu\n", "latency samples", latency_ms.size());
  std::printf("%-40s %12.2f\n", "cmd_vel -> last drive frame p50 [ms]", percentile(latency_ms, 0.5));
  std::printf("%-40s %12.2f\n", "cmd_vel -> last drive frame p90 [ms]", percentile(latency_ms, 0.9));
  std::printf("%-40s %12.2f\n", "cmd_vel -> last drive frame p99 [ms]", percentile(latency_ms, 0.99));
  std::printf("%-40s %12.2f\n", "cmd_vel -> last drive frame max [ms]", percentile(latency_ms, 1.0));
  std::printf(
      "%-40s %12zu\n", "samples above 2 ms",
      static_cast<size_t>(std::count_if(latency_ms.begin(), latency_ms.end(), [](double v) { return v > 2.0; })));
  std::printf("%-40s %12.0f\n", "virtual bus frames/s (2 processes)", bus.fps);
  std::printf("%-40s %12.1f\n", "base_driver CPU at 50 Hz, 9 drives [%]", cpu_pct);
  std::printf(
      "RESULT {\"cmd_to_frame_p50_ms\": %.2f, \"cmd_to_frame_p99_ms\": %.2f, \"virtual_bus_fps\": %.0f, "
      "\"base_driver_cpu_pct_9_drives\": %.1f}\n",
      percentile(latency_ms, 0.5), percentile(latency_ms, 0.99), bus.fps, cpu_pct);
  std::fflush(stdout);
  // End the launch cleanly: the other nodes shut down on request, roslaunch exits once every node is gone.
  for (const char* node : {"/base_driver", "/can_device_sim"}) {
    XmlRpc::XmlRpcValue reply;
    if (!callNode(ros::this_node::getNamespace() + node, "shutdown", "hardware_bench finished", &reply)) {
      std::fprintf(stderr, "hardware_bench: could not ask %s to shut down\n", node);
    }
  }
  // roslaunch keeps its master running after the nodes end: ask it to stop as Ctrl-C would, when it started us.
  std::ifstream parent("/proc/" + std::to_string(::getppid()) + "/cmdline");
  const std::string parent_cmd((std::istreambuf_iterator<char>(parent)), std::istreambuf_iterator<char>());
  if (parent_cmd.find("roslaunch") != std::string::npos) ::kill(::getppid(), SIGINT);
  return latency_ms.size() > 0 ? 0 : 1;
}
