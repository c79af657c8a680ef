#pragma once

// Where the cotton rover believes it is while it drives a field (field_rows.h), and whether it may drive on it:
// FieldPose runs the rover's sensors (rover_sensors.h) after every physics step into the fusion the nodes run
// (RoverFusion: wheel odometry, both IMUs and the RTK receiver) and gives the fused pose in the field's east-north
// frame, the frame its rows' GNSS waypoints are recorded in (through the navsat transform's datum and the receiver's
// local tangent plane). DriveGate stops the rover while the fusion's localization_ok is false (no fix for longer than
// the GNSS timeout, a refused jump, a stale sensor), says why, and lets it go again once the fusion is ok. ROS-free.

#include <memory>
#include <optional>
#include <string>

#include <Eigen/Core>
#include <thorvald_navigation/fusion_monitor.h>

#include "cotton_harvester/control/pure_pursuit.h"
#include "cotton_harvester_sim/rover_fusion.h"
#include "cotton_harvester_sim/rover_sensors.h"

namespace cotton_harvester {
namespace sim {

/// Stop rather than guess: follows the fusion's health; resumes after the fusion has been ok for `resume_after_s`.
class DriveGate {
 public:
  explicit DriveGate(double resume_after_s = 0.5) : resume_after_s_(resume_after_s) {}

  /// The health at `t` [s]. Returns a line when the gate changes ("stopped: <why>", "resumed after <s> s"), else
  /// nothing.
  std::optional<std::string> update(const thorvald_navigation::FusionHealth& health, double t);
  bool stopped() const { return stopped_; }
  /// Why it stopped (the fusion's reasons), empty while driving.
  const std::string& reason() const { return reason_; }
  int stops() const { return stops_; }
  double stoppedTotalS() const { return stopped_total_s_; }

 private:
  double resume_after_s_;
  bool stopped_ = false;
  std::string reason_;
  std::optional<double> ok_since_;
  double stopped_at_ = 0.0, stopped_total_s_ = 0.0;
  int stops_ = 0;
};

/// The rover's fused pose in the field's frame (the GNSS model's east-north-up: the simulation's world frame).
class FieldPose {
 public:
  /// Sensors on `sim` (their realism `sensors`, or the simulation's), one filter of odometry + two IMUs + one GNSS.
  FieldPose(const RoverSim& sim, unsigned seed, const RoverFusionParams& fusion = {},
            std::optional<thorvald_sim::Realism> sensors = std::nullopt);

  /// Call after every physics step: polls the sensors and feeds the filter.
  void afterStep();
  /// The datum is set (the first fixed epoch): poses can be given in the field's frame.
  bool ready() const { return to_enu_.has_value(); }
  /// base_link (the front axle's middle, the front half's heading) in the field's frame at `t` [s]; ready() first.
  control::Pose2 estimate(double t);
  thorvald_navigation::FusionHealth health(double t) const { return fusion_->health(t); }
  /// The filter's own 1-sigma of x, y [m].
  Eigen::Vector2d sigma() const { return fusion_->positionSigma(); }
  const RoverFusion& fusion() const { return *fusion_; }

 private:
  /// The fusion's world frame -> east-north: a similarity (rotation, scale, offset) through the datum.
  struct Similarity {
    double angle = 0.0, scale = 1.0;
    Eigen::Vector2d offset = Eigen::Vector2d::Zero();
  };
  std::optional<Eigen::Vector2d> enuOf(double x, double y) const;

  std::unique_ptr<RoverSensors> sensors_;
  std::unique_ptr<RoverFusion> fusion_;
  thorvald_sim::GeodeticDatum datum_;
  std::optional<Similarity> to_enu_;
};

}  // namespace sim
}  // namespace cotton_harvester
