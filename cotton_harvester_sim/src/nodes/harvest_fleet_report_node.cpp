// harvest_fleet_report: waits for the end-of-run metrics of several rovers harvesting at once, each in its own
// namespace (<rover>/harvest/metrics, diagnostic_msgs/DiagnosticStatus, as mujoco_harvest publishes them), prints
// one line per rover and the fleet's totals, and exits: 0 when every rover reported a run that was done, 1 when one
// reported an error, did not report before ~timeout_s (wall time) or the parameters are bad.
#include <map>
#include <string>
#include <vector>

#include <diagnostic_msgs/DiagnosticStatus.h>
#include <ros/ros.h>
#include <thorvald_common/ros/param_reader.h>

namespace {

double valueOf(const diagnostic_msgs::DiagnosticStatus& s, const std::string& key) {
  for (const auto& kv : s.values) {
    if (kv.key != key) continue;
    try {
      return std::stod(kv.value);
    } catch (const std::exception&) {
      return 0.0;
    }
  }
  return 0.0;
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "harvest_fleet_report");
  ros::NodeHandle nh, pnh("~");
  std::vector<std::string> rovers;
  double timeout_s = 0.0;
  try {
    thorvald_common::ParamReader reader(pnh);
    rovers = reader.texts("rovers", {"rover1", "rover2"}, 1, 16, true);
    timeout_s = reader.number("timeout_s", 3600.0, thorvald_common::ParamRange::aboveUpTo(0.0, 86400.0), "s");
    reader.finish();
  } catch (const thorvald_common::ParamError& e) {
    ROS_FATAL("%s", e.what());
    return 1;
  }
  std::map<std::string, diagnostic_msgs::DiagnosticStatus> reports;
  std::vector<ros::Subscriber> subscribers;
  for (const std::string& rover : rovers) {
    subscribers.push_back(nh.subscribe<diagnostic_msgs::DiagnosticStatus>(
        rover + "/harvest/metrics", 1,
        [&reports, rover](const diagnostic_msgs::DiagnosticStatus::ConstPtr& msg) { reports[rover] = *msg; }));
  }
  const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(timeout_s);
  ros::WallRate poll(10.0);
  while (ros::ok() && reports.size() < rovers.size() && ros::WallTime::now() < deadline) {
    ros::spinOnce();
    poll.sleep();
  }
  int failed = 0;
  double picked = 0.0, present = 0.0, time_s = 0.0;
  for (const std::string& rover : rovers) {
    const auto it = reports.find(rover);
    if (it == reports.end()) {
      ROS_ERROR("harvest_fleet_report: %s reported no metrics", rover.c_str());
      ++failed;
      continue;
    }
    const diagnostic_msgs::DiagnosticStatus& s = it->second;
    if (s.level != diagnostic_msgs::DiagnosticStatus::OK) ++failed;
    picked += valueOf(s, "picked");
    present += valueOf(s, "bolls_present");
    time_s = std::max(time_s, valueOf(s, "time_s"));
    ROS_INFO("harvest_fleet_report: %s: %s; picked %.0f of %.0f, CT %.1f s, ASR %.1f %%, time %.1f s", rover.c_str(),
             s.message.c_str(), valueOf(s, "picked"), valueOf(s, "bolls_present"), valueOf(s, "ct_s"),
             valueOf(s, "asr_pct"), valueOf(s, "time_s"));
  }
  if (present > 0.0)
    ROS_INFO(
        "harvest_fleet_report: fleet of %zu: picked %.0f of %.0f (ASR %.1f %%) in %.1f s of simulated time, "
        "%.2f bolls/s",
        rovers.size(), picked, present, 100.0 * picked / present, time_s, time_s > 0.0 ? picked / time_s : 0.0);
  return failed == 0 ? 0 : 1;
}
