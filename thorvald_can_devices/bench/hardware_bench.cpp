// Hardware-mode figures, run inside launch/hardware_bench.launch (base_driver + can_device_sim, 9 drives):
//  - latency from a twist_mux/cmd_vel message to the last drive's command frame on the bus (p50, p99);
//  - frames per second the virtual bus carries between two processes;
//  - base_driver's CPU at 50 Hz with 9 drives (from /proc/<pid>/stat, pid asked from the node itself).
//   roslaunch thorvald_can_devices hardware_bench.launch
#include <geometry_msgs/Twist.h>
#include <ros/master.h>
#include <ros/network.h>
#include <ros/ros.h>
#include <unistd.h>
#include <xmlrpcpp/XmlRpcClient.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <vector>

#include "bus_throughput.h"
#include "thorvald_can_devices/drive_scaling.h"
#include "thorvald_can_devices/thorvald_drive_protocol.h"
#include "thorvald_can_devices/virtual_can_bus.h"

using namespace thorvald_can_devices;

namespace {

int nodePid(const std::string& node) {
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = ros::this_node::getName();
  args[1] = node;
  if (!ros::master::execute("lookupNode", args, result, payload, false)) return -1;
  std::string uri = static_cast<std::string>(payload);
  std::string host;
  uint32_t port = 0;
  if (!ros::network::splitURI(uri, host, port)) return -1;
  XmlRpc::XmlRpcClient client(host.c_str(), port, "/");
  XmlRpc::XmlRpcValue a, r;
  a[0] = ros::this_node::getName();
  if (!client.execute("getPid", a, r) || r.size() < 3) return -1;
  return static_cast<int>(r[2]);
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

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(p * (v.size() - 1) + 0.5))];
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "hardware_bench");
  ros::NodeHandle nh, pnh("~");
  const std::string bus_name = pnh.param<std::string>("bus", "bench");
  const int samples = pnh.param("samples", 200);
  const int last_node = pnh.param("last_node", 9);
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
  std::printf("%-40s %12.2f\n", "cmd_vel -> last drive frame p99 [ms]", percentile(latency_ms, 0.99));
  std::printf("%-40s %12.0f\n", "virtual bus frames/s (2 processes)", bus.fps);
  std::printf("%-40s %12.1f\n", "base_driver CPU at 50 Hz, 9 drives [%]", cpu_pct);
  std::printf(
      "RESULT {\"cmd_to_frame_p50_ms\": %.2f, \"cmd_to_frame_p99_ms\": %.2f, \"virtual_bus_fps\": %.0f, "
      "\"base_driver_cpu_pct_9_drives\": %.1f}\n",
      percentile(latency_ms, 0.5), percentile(latency_ms, 0.99), bus.fps, cpu_pct);
  return latency_ms.size() > 0 ? 0 : 1;
}
