// mujoco_harvest: one harvest of a simulated cotton row in MuJoCo (the rover, its camera through the perception
// pipeline, the harvest state machine, the deadband position control of the hydrostatic drive, picks decided by the
// simulated vacuum), headless. Publishes the machine's status while it runs and the run's metrics at the end,
// writes the metrics CSV, the path PNG and a debug frame when asked, prints the Table 2/3 row and exits: 0 when
// the run was done (any machine outcome), 1 when it could not be (bad parameters, the model or renderer failed).
#include <cstdio>
#include <memory>
#include <string>

#include <diagnostic_msgs/DiagnosticStatus.h>
#include <ros/ros.h>
#include <thorvald_common/ros/param_reader.h>
#include <thorvald_state_machine/MachineStatus.h>
#include <thorvald_state_machine/ros/status_publisher.h>

#include "cotton_harvester_sim/harvest_run.h"
#include "field_rows_experiment.h"
#include "harvest_metrics_status.h"

namespace {

using cotton_harvester::sim::HarvestRunConfig;
using cotton_harvester::sim::HarvestRunReport;
using thorvald_common::ParamRange;

HarvestRunConfig readConfig(thorvald_common::ParamReader& r) {
  const std::string experiment = r.choice("experiment", "potted", {"potted", "field"});
  const int seed = r.integer("seed", 1, 0, 1000000);
  HarvestRunConfig c = experiment == "field" ? cotton_harvester::sim::fieldConfig(static_cast<unsigned>(seed))
                                             : cotton_harvester::sim::pottedConfig(static_cast<unsigned>(seed));
  c.sim.realism = *thorvald_sim::realismFromName(r.choice("realism", "ideal", {"ideal", "datasheet"}));
  c.sim.row.plants = r.integer("plants", c.sim.row.plants, 1, 60);
  c.sim.row.bolls_per_plant = r.integer("bolls_per_plant", c.sim.row.bolls_per_plant, 0, 10);
  c.sim.row.slope_deg = r.number("slope_deg", c.sim.row.slope_deg, ParamRange::closed(-15.0, 15.0), "deg");
  c.machine.row_length_m = r.number("row_length_m", c.machine.row_length_m, ParamRange::aboveUpTo(0.0, 100.0), "m");
  c.machine.remember_target_frames = r.integer("remember_target_frames", c.machine.remember_target_frames, 0, 20);
  c.machine.keep_target = r.flag("keep_target", c.machine.keep_target);
  c.machine.revisit_pending = r.flag("revisit_pending", c.machine.revisit_pending);
  const std::string order = r.choice("target_order", "along_row", {"along_row", "range"});
  c.machine.tracker.order = order == "range" ? cotton_harvester::control::TargetOrder::kRange
                                             : cotton_harvester::control::TargetOrder::kAlongRow;
  c.time_limit_s = r.number("time_limit_s", c.time_limit_s, ParamRange::aboveUpTo(0.0, 36000.0), "s");
  c.machine.actions.clear_leaves_before_pick =
      r.flag("clear_leaves_before_pick", c.machine.actions.clear_leaves_before_pick);
  c.effector_search_near_arm = r.flag("effector_search_near_arm", c.effector_search_near_arm);
  c.partial_bolls = r.flag("partial_bolls", c.partial_bolls);
  c.machine.search_under_leaves = r.flag("search_under_leaves", c.machine.search_under_leaves);
  c.debug_image_path = r.text("debug_image", "");
  return c;
}

diagnostic_msgs::DiagnosticStatus metricsMsg(const HarvestRunReport& report, const std::string& run) {
  diagnostic_msgs::DiagnosticStatus s;
  s.name = "harvest: " + run;
  s.level = report.error.empty() ? diagnostic_msgs::DiagnosticStatus::OK : diagnostic_msgs::DiagnosticStatus::ERROR;
  s.message = report.error.empty() ? report.outcome : report.error;
  const auto add = [&s](const std::string& key, double value) { cotton_harvester::sim::addMetric(&s, key, value); };
  cotton_harvester::sim::addRunMetrics(&s, report.counts, report.metrics, report.bolls_reachable, report.machine_picked,
                                       report.sim_time_s, report.wall_time_s, report.frames);
  add("ee_fallback_frames", report.effector_from_calibration);
  add("picks_cleared", report.picks_cleared);
  add("hidden_from_row", report.misses.count[static_cast<int>(cotton_harvester::sim::MissCause::kHiddenFromRow)]);
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "mujoco_harvest");
  ros::NodeHandle nh, pnh("~");
  // A whole field, row after row (rows, row_length_m, seed, realism, path_png, waypoints).
  if (pnh.param<std::string>("experiment", "potted") == "field_rows")
    return cotton_harvester::sim::runFieldRowsExperiment(nh, pnh);
  HarvestRunConfig config;
  std::string metrics_csv, path_png, run_name;
  try {
    thorvald_common::ParamReader reader(pnh);
    config = readConfig(reader);
    metrics_csv = reader.text("metrics_csv", "");
    path_png = reader.text("path_png", "");
    run_name = reader.text("run_name", "mujoco_harvest");
    reader.finish();
  } catch (const thorvald_common::ParamError& e) {
    ROS_FATAL("%s", e.what());
    return 1;
  }
  ros::Publisher status_pub = nh.advertise<thorvald_state_machine::MachineStatus>("harvest/machine_status", 100, true);
  ros::Publisher metrics_pub = nh.advertise<diagnostic_msgs::DiagnosticStatus>("harvest/metrics", 1, true);
  config.status_observer = [&status_pub](const thorvald_state_machine::StatusSnapshot& snapshot) {
    status_pub.publish(thorvald_state_machine::toMsg(snapshot, ros::Time::now()));
  };
  ROS_INFO("mujoco_harvest: %d plants x %d bolls, slope %.4f deg, %.2f m of row", config.sim.row.plants,
           config.sim.row.bolls_per_plant, config.sim.row.slope_deg, config.machine.row_length_m);
  const HarvestRunReport report = cotton_harvester::sim::runHarvest(config);
  metrics_pub.publish(metricsMsg(report, run_name));
  if (!report.error.empty()) {
    ROS_FATAL("mujoco_harvest: the run could not be done: %s", report.error.c_str());
    ros::Duration(0.5).sleep();  // let the latched metrics reach their subscribers
    return 1;
  }
  const auto& c = report.counts;
  const auto& m = report.metrics;
  ROS_INFO(
      "mujoco_harvest: %s; bolls %d (reachable %d), detected %d, reached %d, picked %d; time %.1f s, CT %.1f s, "
      "ASR %.1f %%, DP %.1f %%, MRR %.1f %%, OV %.2f cm/s; %d frames; %.2fx real time",
      report.outcome.c_str(), c.bolls_present, report.bolls_reachable, c.detected, c.reached, c.picked, c.time_s,
      m.cycle_time_s.value_or(0.0), m.action_success_pct.value_or(0.0), m.detection_performance_pct.value_or(0.0),
      m.reaching_ratio_pct.value_or(0.0), m.operation_velocity_cm_s, report.frames,
      report.wall_time_s > 0 ? report.sim_time_s / report.wall_time_s : 0.0);
  std::string error;
  if (!metrics_csv.empty() && !cotton_harvester::control::appendCsv(metrics_csv, run_name, c, m, &error))
    ROS_ERROR("mujoco_harvest: %s", error.c_str());
  if (!path_png.empty() && !cotton_harvester::sim::writePathPng(report, path_png))
    ROS_ERROR("mujoco_harvest: could not write %s", path_png.c_str());
  ros::Duration(0.5).sleep();  // let the latched status and metrics reach their subscribers before exiting
  return 0;
}
