// uv_dose: the UV dose per metre of row of each rail set, from the lamps' state and the wheel odometry along the rails
// (UvDoseRecorder). Each time the robot leaves the rails it writes a PNG strip per set and the YAML report to
// ~output_dir and publishes the report on mission/dose (latched); again when the node stops.
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <std_msgs/Bool.h>
#include <std_msgs/String.h>
#include <thorvald_common/ros/param_reader.h>
#include <thorvald_common/ros/run_node.h>

#include <fstream>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "greenhouse_rail_nav/SurfaceState.h"
#include "greenhouse_rail_nav/uv_dose.h"

namespace greenhouse_rail_nav {
namespace {

using thorvald_common::ParamRange;

double yawOf(const geometry_msgs::Quaternion& q) {
  return std::atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z));
}

UvDoseParams readDoseParams(thorvald_common::ParamReader& r) {
  UvDoseParams p;
  p.lamp_power_w = r.number("lamp_power", p.lamp_power_w, ParamRange::aboveUpTo(0.0, 10000.0), "W");
  p.lamp_length_m = r.number("lamp_length", p.lamp_length_m, ParamRange::aboveUpTo(0.0, 5.0), "m");
  p.lamp_offset_m = r.number("lamp_offset", p.lamp_offset_m, ParamRange::closed(-5.0, 5.0), "m");
  p.target_dose_j_per_m = r.number("target_dose", p.target_dose_j_per_m, ParamRange::aboveUpTo(0.0, 1e6), "J/m");
  p.bin_m = r.number("resolution", p.bin_m, ParamRange::aboveUpTo(0.0, 1.0), "m");
  if (const std::string e = p.validate(); !e.empty()) throw thorvald_common::ParamError("uv_dose: " + e);
  return p;
}

class UvDoseNode {
 public:
  UvDoseNode(ros::NodeHandle& nh, ros::NodeHandle& pnh) : recorder_(UvDoseParams{}, 0.0) {
    thorvald_common::ParamReader r(pnh);
    const UvDoseParams p = readDoseParams(r);
    const double row_length = r.number("rail_length", 0.0, ParamRange::closed(0.0, 500.0), "m");
    const double same_set = r.number("same_set_distance", 0.5, ParamRange::aboveUpTo(0.0, 5.0), "m");
    output_dir_ = r.text("output_dir", std::string(getenv("HOME") ? getenv("HOME") : "/tmp") + "/.ros/uv_dose");
    r.finish();
    recorder_ = UvDoseRecorder(p, row_length, same_set);
    if (!output_dir_.empty() && system(("mkdir -p '" + output_dir_ + "'").c_str()) != 0)
      throw thorvald_common::ParamError("uv_dose: cannot create ~output_dir " + output_dir_);
    report_pub_ = nh.advertise<std_msgs::String>("mission/dose", 1, true);
    subs_.push_back(
        nh.subscribe<std_msgs::Bool>("lamps", 5, [this](const std_msgs::Bool::ConstPtr& m) { lamps_ = m->data; }));
    subs_.push_back(nh.subscribe<SurfaceState>("surface_monitor/state", 5, [this](const SurfaceState::ConstPtr& m) {
      on_rails_ = m->wheels == SurfaceState::RAIL;
    }));
    subs_.push_back(
        // The fused odometry, as uv_mission's: positions along the rails are its displacement along the entry's
        // heading, which a wheel stalling against a pipe would turn in the wheels' odometry alone.
        nh.subscribe<nav_msgs::Odometry>("odometry/filtered", 50, [this](const nav_msgs::Odometry::ConstPtr& m) {
          const int before = recorder_.currentSet();
          const auto& pose = m->pose.pose;
          recorder_.update(m->header.stamp.toSec(), pose.position.x, pose.position.y, yawOf(pose.orientation),
                           on_rails_, lamps_);
          if (before >= 0 && recorder_.currentSet() < 0) write();  // off the rails: report what that pass gave
        }));
    ROS_INFO("uv_dose: %.0f W over %.2f m (centre %.3f m along x), target %.0f J/m; lamps on %s; reports in %s",
             p.lamp_power_w, p.lamp_length_m, p.lamp_offset_m, p.target_dose_j_per_m, nh.resolveName("lamps").c_str(),
             output_dir_.c_str());
  }
  ~UvDoseNode() { write(); }

 private:
  void write() {
    if (recorder_.sets() == 0) return;
    std::vector<RowDose> rows;
    for (std::size_t i = 0; i < recorder_.sets(); ++i) rows.push_back(recorder_.dose(i));
    std::vector<SetDoseReport> sets;
    for (std::size_t i = 0; i < rows.size(); ++i) {
      std::string png;
      if (!output_dir_.empty()) {
        png = output_dir_ + "/set" + std::to_string(i) + "_dose.png";
        if (!cv::imwrite(png, doseStrip(rows[i]))) ROS_WARN("uv_dose: cannot write %s", png.c_str());
      }
      sets.push_back({static_cast<int>(i), png, &rows[i]});
      ROS_INFO("uv_dose: set %zu: %.1f %% of %.2f m at >= %.0f J/m (min %.1f, mean %.1f J/m)", i,
               100.0 * rows[i].coverage(), rows[i].rowLength(), rows[i].params().target_dose_j_per_m, rows[i].minDose(),
               rows[i].meanDose());
    }
    std_msgs::String msg;
    msg.data = doseReportYaml(sets);
    report_pub_.publish(msg);
    if (!output_dir_.empty()) std::ofstream(output_dir_ + "/uv_dose.yaml") << msg.data;
  }

  UvDoseRecorder recorder_;
  std::string output_dir_;
  bool lamps_ = false, on_rails_ = false;
  std::vector<ros::Subscriber> subs_;
  ros::Publisher report_pub_;
};

}  // namespace
}  // namespace greenhouse_rail_nav

int main(int argc, char** argv) {
  return thorvald_common::runNode<greenhouse_rail_nav::UvDoseNode>(argc, argv, "uv_dose");
}
