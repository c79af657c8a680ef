#include "field_rows_experiment.h"

#include <diagnostic_msgs/DiagnosticArray.h>
#include <diagnostic_msgs/DiagnosticStatus.h>
#include <std_msgs/String.h>
#include <thorvald_common/ros/param_reader.h>

#include "cotton_harvester_sim/field_rows.h"
#include "harvest_metrics_status.h"

namespace cotton_harvester {
namespace sim {

namespace {

diagnostic_msgs::DiagnosticStatus fieldMetrics(const FieldRowsReport& r, const std::string& run) {
  diagnostic_msgs::DiagnosticStatus s;
  s.name = "field_rows: " + run;
  s.level = r.error.empty() ? diagnostic_msgs::DiagnosticStatus::OK : diagnostic_msgs::DiagnosticStatus::ERROR;
  s.message = r.error.empty() ? "finished" : r.error;
  addMetric(&s, "rows", static_cast<double>(r.field.row_start.size()));
  addMetric(&s, "rows_completed_pct", r.rows_completed_pct);
  addMetric(&s, "row_end_turn_success_pct", r.turn_success_pct);
  addMetric(&s, "cross_track_rms_m", r.cross_track_rms_m);
  addMetric(&s, "time_s", r.sim_time_s);
  addMetric(&s, "localization_stops", static_cast<double>(r.stops));
  addMetric(&s, "localization_stopped_s", r.stopped_s);
  return s;
}

}  // namespace

int runFieldRowsExperiment(ros::NodeHandle& nh, ros::NodeHandle& pnh) {
  FieldRowsConfig config;
  std::string path_png, run_name;
  try {
    thorvald_common::ParamReader r(pnh);
    r.text("experiment", "field_rows");
    const int rows = r.integer("rows", 4, 1, 40);
    const double length = r.number("row_length_m", 20.0, thorvald_common::ParamRange::aboveUpTo(0.0, 200.0), "m");
    config = fieldRowsConfig(rows, length, static_cast<unsigned>(r.integer("seed", 1, 0, 1000000)));
    config.sim.realism = *thorvald_sim::realismFromName(r.choice("realism", "ideal", {"ideal", "datasheet"}));
    config.time_limit_s = r.number("time_limit_s", 600.0 + rows * (length / 0.25 + 120.0),
                                   thorvald_common::ParamRange::aboveUpTo(0.0, 36000.0), "s");
    config.waypoints_path = r.text("waypoints", "");
    config.fused_pose = r.choice("pose", "fused", {"fused", "odometry"}) == "fused";
    path_png = r.text("path_png", "");
    run_name = r.text("run_name", "field_rows");
    r.finish();
  } catch (const thorvald_common::ParamError& e) {
    ROS_FATAL("%s", e.what());
    return 1;
  }
  ros::Publisher progress_pub = nh.advertise<std_msgs::String>("harvest/field_progress", 100, true);
  ros::Publisher metrics_pub = nh.advertise<diagnostic_msgs::DiagnosticStatus>("harvest/metrics", 1, true);
  ros::Publisher diagnostics_pub = nh.advertise<diagnostic_msgs::DiagnosticArray>("diagnostics", 10);
  config.progress = [&progress_pub, &diagnostics_pub](const std::string& line) {
    ROS_INFO("%s", line.c_str());
    std_msgs::String msg;
    msg.data = line;
    progress_pub.publish(msg);
    // The drive gate: stopped on the fusion's localization_ok (why), resumed when it is ok again.
    const bool stopped = line.find("stopped: ") != std::string::npos;
    if (!stopped && line.find("resumed: ") == std::string::npos) return;
    diagnostic_msgs::DiagnosticArray array;
    array.header.stamp = ros::Time::now();
    diagnostic_msgs::DiagnosticStatus status;
    status.name = "field_rows: drive gate";
    status.level = stopped ? diagnostic_msgs::DiagnosticStatus::WARN : diagnostic_msgs::DiagnosticStatus::OK;
    status.message = line;
    array.status.push_back(status);
    diagnostics_pub.publish(array);
  };
  ROS_INFO("mujoco_harvest: field_rows, %d rows x %.1f m, %.4f m apart, pose %s", config.field.rows,
           config.field.row_length_m, config.field.row_spacing_m,
           config.fused_pose ? "fused (odometry, two IMUs, RTK GNSS)" : "from the wheel odometry");
  const FieldRowsReport report = runFieldRows(config);
  for (const auto& row : report.rows)
    ROS_INFO("field_rows: row %d %s: cross-track rms %.3f m, max %.3f m; pose off by %.3f m at its end; %.0f s",
             row.row, row.completed ? "completed" : "NOT completed", row.cross_track_rms_m, row.cross_track_max_m,
             row.odometry_error_m, row.time_s);
  for (const auto& t : report.turns)
    ROS_INFO("field_rows: turn after row %d %s: entry %.3f m, %.1f deg; %.2f m deep (planned %.2f)", t.from_row,
             t.success ? "entered" : "FAILED", t.entry_cross_track_m, t.entry_heading_deg, t.depth_m,
             t.planned_depth_m);
  metrics_pub.publish(fieldMetrics(report, run_name));
  if (!path_png.empty() && !writeFieldPng(report, path_png))
    ROS_ERROR("mujoco_harvest: could not write %s", path_png.c_str());
  ros::Duration(0.5).sleep();  // let the latched messages reach their subscribers
  if (!report.error.empty()) {
    ROS_FATAL("mujoco_harvest: field_rows: %s", report.error.c_str());
    return 1;
  }
  ROS_INFO("mujoco_harvest: field_rows: rows completed %.0f %%, turns %.0f %%, cross-track rms %.3f m",
           report.rows_completed_pct, report.turn_success_pct, report.cross_track_rms_m);
  return 0;
}

}  // namespace sim
}  // namespace cotton_harvester
