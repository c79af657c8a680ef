#pragma once

#include <ros/ros.h>

namespace cotton_harvester {
namespace sim {

/// mujoco_harvest experiment:=field_rows: the rover drives a generated field row after row (field_rows.h), prints a
/// progress line per leg (and publishes it on harvest/field_progress), a report per row and per turn, publishes the
/// run's figures on harvest/metrics and writes the field's PNG (~path_png) and its waypoints (~waypoints). Returns
/// main's exit code: 0 when the field was driven, 1 when the run could not be done or the parameters are bad.
int runFieldRowsExperiment(ros::NodeHandle& nh, ros::NodeHandle& pnh);

}  // namespace sim
}  // namespace cotton_harvester
