#pragma once

#include <string>

#include "cotton_harvester/control/waypoint_path.h"

namespace cotton_harvester {
namespace control {

/// Pure pursuit for the centre-articulated rover (paper §2.1, §4: path following along the rows with RTK-GNSS).
/// The pose is the front axle's centre with the front half's heading, as ArticulatedOdometry integrates it: for equal
/// half lengths a (axle to joint) the front axle then turns with curvature tan(gamma / 2) / a at articulation gamma.
struct PurePursuitParams {
  double lookahead_m = 1.2;              ///< lookahead at rest [m] ...
  double lookahead_per_mps = 2.0;        ///< ... growing with the speed [s] ...
  double min_lookahead_m = 0.8;          ///< ... and kept within these limits [m]
  double max_lookahead_m = 3.0;          ///< [m]
  double axle_to_joint_m = 0.91;         ///< both axles to the articulation joint (paper §2.1) [m]
  double articulation_limit_deg = 45.0;  ///< the set-point never asks more (paper §2.3) [deg]
  double goal_tolerance_m = 0.05;        ///< the path is done when the projection is this close to its end [m]
  double search_window_m = 3.0;          ///< the projection looks this far ahead of the last one (never back) [m]
  /// Heading correction: where the path is straight (its heading within straight_path_deg from the projection to
  /// the goal), the heading the pose reports is corrected by the integral of the cross-track over the distance
  /// driven times this gain [rad per m of cross-track per m driven; 0: off]. A pose whose heading is off by delta
  /// (a fused yaw that drifted in a turn) otherwise holds the rover lookahead * tan(delta) beside a straight row;
  /// the correction removes that steady offset and carries over to the next path (the heading's error persists).
  double heading_correction_gain = 0.0;
  double heading_correction_limit_deg = 5.0;  ///< |correction| never more [deg]
  double straight_path_deg = 1.0;             ///< the path counts as straight within this [deg]
  /// ... and the rover settled on it: the previous step asked at most this articulation [deg] (after a turn the
  /// rover swings onto the row with the cross-track of its lag, which is not the heading's error)
  double settled_articulation_deg = 2.0;

  /// Empty when sound, otherwise "key: expected ...".
  std::string check() const;
};

/// One step of the follower.
struct PursuitStep {
  double articulation_deg = 0.0;        ///< set-point for the articulation controller, within the limit [deg]
  double curvature_1pm = 0.0;           ///< curvature pure pursuit asks (before the limit) [1/m]
  double cross_track_m = 0.0;           ///< front axle to the path, positive left of it [m]
  double heading_error_rad = 0.0;       ///< path heading minus the rover's at the projection [rad]
  double lookahead_m = 0.0;             ///< the lookahead used [m]
  double s_m = 0.0;                     ///< progress along the path [m]
  double heading_correction_rad = 0.0;  ///< added to the pose's heading (heading_correction_gain) [rad]
  double remaining_m = 0.0;             ///< path length still ahead [m]
  bool finished = false;
};

/// Articulation [deg] that gives the front axle a curvature [1/m]: gamma = 2 atan(a kappa).
double articulationForCurvature(double curvature_1pm, double axle_to_joint_m);
/// The front axle's curvature [1/m] at an articulation [deg]: tan(gamma / 2) / a.
double curvatureForArticulation(double articulation_deg, double axle_to_joint_m);
/// The smallest turning radius of the front axle at an articulation [deg] (45 deg, 0.91 m: 2.20 m).
double minTurnRadius(double articulation_deg, double axle_to_joint_m);

/// Follows a WaypointPath: projects the front axle onto the path (searching forward only, so a neighbouring row or
/// the far side of a turn is never taken for the path), aims at the point one lookahead further along it
/// (extrapolated straight past the end) and returns the articulation that puts the front axle on the circle
/// through it. Deterministic; the caller's control loop sets the rate.
class PurePursuit {
 public:
  /// Throws std::invalid_argument when params fail check().
  explicit PurePursuit(const PurePursuitParams& params = PurePursuitParams());

  /// A new path; progress starts at its beginning. The heading correction is kept.
  void setPath(const WaypointPath& path);
  /// Forgets the heading correction (a new pose source).
  void resetHeadingCorrection();
  /// Lookahead for a speed [m/s] within the limits [m].
  double lookahead(double speed_mps) const;
  /// One step at the front axle's pose and the rover's speed [m/s]. Without a path: straight, finished.
  PursuitStep update(const Pose2& front_axle, double speed_mps);

  const WaypointPath& path() const { return path_; }
  double progressM() const { return s_m_; }
  const PurePursuitParams& params() const { return params_; }

 private:
  PurePursuitParams params_;
  WaypointPath path_;
  double s_m_ = 0.0;
  double heading_correction_rad_ = 0.0;
  bool has_last_ = false;
  double last_articulation_deg_ = 0.0;
  Eigen::Vector2d last_ = Eigen::Vector2d::Zero();  ///< the front axle at the previous update [m]
};

}  // namespace control
}  // namespace cotton_harvester
