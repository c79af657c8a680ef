#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include <thorvald_state_machine/state_machine.h>

#include "greenhouse_rail_nav/obstacle_zones.h"
#include "greenhouse_rail_nav/odometry_motion.h"
#include "thorvald_base/pose2d.h"
#include "greenhouse_rail_nav/rail_alignment.h"
#include "greenhouse_rail_nav/rail_run.h"
#include "greenhouse_rail_nav/surface_classifier.h"

namespace greenhouse_rail_nav {

/// The latest rail detection, as the mission sees it.
struct RailObservation {
  enum class Status { kNone, kFound, kXUnobserved, kNotFound };
  Status status = Status::kNone;
  double stamp_s = -1.0;                ///< time of the depth cloud it came from [s]
  thorvald_base::Pose2D robot_in_rail;  ///< base_link in the rail frame
};

/// The surfaces under the robot (from the surface monitor).
struct SurfaceReading {
  Surface front = Surface::kUnknown;   ///< common surface of the sensors ahead of the wheels
  Surface wheels = Surface::kUnknown;  ///< common surface of the sensors at the drive wheels
  double stamp_s = -1.0;
};

enum class NavState { kIdle, kActive, kSucceeded, kFailed };

/// Everything the mission needs of the robot, so that the mission logic runs the same against ROS (the node)
/// and against a simulated robot in a unit test. Called from the mission's thread only.
class MissionIO {
 public:
  virtual ~MissionIO() = default;
  virtual double now() = 0;     ///< [s]
  virtual bool ok() = 0;        ///< false when the process shuts down
  virtual void waitTick() = 0;  ///< waits one control period
  virtual void sendNavGoal(const thorvald_base::Pose2D& map_pose) = 0;
  virtual NavState navState(std::string* reason) = 0;
  virtual void cancelNav() = 0;
  virtual bool odomPose(thorvald_base::Pose2D* pose) = 0;  ///< latest odometry pose; false when none (or stale)
  virtual bool mapPose(thorvald_base::Pose2D* pose) = 0;   ///< robot in the map frame; false when unknown
  virtual RailObservation railObservation() = 0;
  virtual SurfaceReading surface() = 0;
  virtual double forwardRange() = 0;  ///< lidar distance straight ahead [m]; NaN when nothing is seen
  /// True while a person must clear a safety stop (bumper); `why` says which.
  virtual bool safetyStopped(std::string* why) = 0;
  virtual void commandTwist(double linear_mps, double angular_rps) = 0;
  virtual void setLights(bool on) = 0;
  /// Tells the localisation where the robot stands (the pose stored before entering the rails).
  virtual void resetLocalisation(const thorvald_base::Pose2D& map_pose) = 0;
  virtual void log(const std::string& line) = 0;
  /// What the mission is doing, for the protected zone's shape (obstacle_zones.h); the robot evaluates each scan
  /// against the latest context.
  virtual void setZoneContext(const ZoneContext& /*ctx*/) {}
  /// The protected zone at the latest scan. Without a people and obstacle detector: never blocked, and the far end's
  /// range is forwardRange() (any return ahead is the far wall).
  virtual ZoneVerdict zone() {
    ZoneVerdict v;
    v.end_range_m = forwardRange();
    return v;
  }
  /// True while the lamps' relay board does not confirm its outputs (base_driver's io/<board>/state_unknown).
  virtual bool lightsInDoubt(std::string* /*why*/) { return false; }
  /// The lamps' confirmed state (the relay board's echo of its output, io/<board>/out<k>/state): returns true with
  /// `*on` when the robot reports one; false without (the mission then counts its own light request as lit).
  virtual bool lampsConfirmed(bool* /*on*/) { return false; }
  /// Whether the mission needs rail detections now (true while it waits for one): a robot may pause its detector
  /// in between.
  virtual void wantRailDetection(bool /*on*/) {}
};

/// One rail set to treat: where to stand in front of it (map frame) and the analyzer's verdict.
struct MissionTarget {
  int index = 0;
  thorvald_base::Pose2D target_pose;  ///< map frame, facing the rails
  bool good = true;                   ///< false: the map analyzer was not sure of it; the mission skips it
  std::string note;                   ///< the analyzer's reason when not good
  double rail_length_m = 0.0;  ///< the set's length from its rail start [m]; 0: unknown (any return ahead ends it)
};

struct UvMissionParams {
  AlignmentParams alignment;
  MotionLimits motion;
  RailRunParams rail_run;
  double nav_timeout_s = 180.0;  ///< [s]
  int nav_attempts = 2;
  double detect_timeout_s = 3.0;  ///< wait for a fresh detection [s]
  double detect_settle_s = 0.3;   ///< a detection must come from a cloud taken this long after stopping [s]
  double search_step_rad = 0.15;  ///< rail search: first angle and growth [rad]
  double search_limit_rad = 0.6;  ///< rail search: largest angle [rad]
  int max_align_attempts = 5;
  double enter_speed_mps = 0.1;       ///< [m/s]
  double enter_max_distance_m = 1.6;  ///< beyond this without reaching the rails, entering failed [m]
  /// While entering, the robot follows the rails' centre line (rail frame from the last detection, carried on
  /// by odometry) with this natural frequency [rad/s]; 0 drives straight on as the paper's robot does.
  double enter_line_frequency_rps = 0.8;
  double surface_timeout_s = 0.5;  ///< surface readings older than this stop the robot [s]
  /// Entering, the range finders must read rail under the front and the wheels over this distance before the
  /// robot counts as on the rails (their cones see a pipe before the rail wheels are carried by it) [m].
  double on_rails_margin_m = 0.1;
  /// After a failure at a rail set (a return without floor, an entry or alignment that failed) the robot must be
  /// on the headland floor before the mission goes on: this long for a fresh and decided reading under the
  /// wheels [s].
  double secure_wait_s = 1.0;
  /// With rail still under the wheels after such a failure, the robot reverses at the slow speed at most this
  /// far to find the floor; beyond it the mission stops [m].
  double recover_reverse_max_m = 1.0;
  /// People and obstacles: the protected zone, and how long it must be clear before the mission goes on.
  ZoneParams zone;
  /// A set counts as treated only when this share of its length was passed with the lights on (at no more than the
  /// treatment speed: every metre got at least the dose). With the lamps' confirmed state (MissionIO::lampsConfirmed)
  /// a metre counts as lit only while the relay confirmed the lamps on, not from the mission's own request.
  double min_lit_fraction = 0.99;
  /// After a stop for the zone on the rails, reverse to the last lit point before the lights go on again (the
  /// robot brakes past it with the lights off); this much further back [m].
  double relight_overlap_m = 0.1;
  /// ... and this much more when the lamps were on at the stop: the row under them got part of its dose, and an
  /// interlock lights them again only once the robot is back at the treatment speed (uv_interlock: 0.4 m/s, reached
  /// after 0.16 m at 0.5 m/s^2), so they must come on behind that stretch [m].
  double relight_run_up_m = 0.2;

  std::string validate() const;
};

/// What happened at one rail set.
struct RailSetReport {
  int index = 0;
  bool treated = false;
  std::string result;      ///< "treated", or why not
  int align_attempts = 0;  ///< alignments executed (0: the first detection was within the limits)
  int entry_attempts = 0;
  int searches = 0;
  double rail_length_m = 0.0;   ///< driven on the rails (odometry) [m]
  double lights_on_s = 0.0;     ///< [s]
  double speed_mean_mps = 0.0;  ///< odometry speed while the lights were on, cruise part [m/s]
  double speed_std_mps = 0.0;
  double duration_s = 0.0;  ///< from leaving for the target to being back [s]
  double lit_pct = 0.0;     ///< share of the rails driven that was passed with the lights on [%]
  int pauses = 0;           ///< stops for a person, an obstacle, a safety stop or a relay board in doubt
};

/// The greenhouse UV-treatment mission (greenhouse paper §V-A): for each good rail set, navigate to its target
/// pose, detect the rails (search by rotating if not found), align on odometry until the detection is within
/// the limits, enter slowly while the range finders watch for the floor's edge, treat at 0.5 m/s with the
/// lights on until the far wall says the rail ends, come back, and go on with the next set. Runs as a
/// thorvald_state_machine machine (status and history for introspection); preemptable; a later run resumes at
/// the first set not treated yet.
class UvMission {
 public:
  UvMission(MissionIO& io, const UvMissionParams& params, std::vector<MissionTarget> targets);
  ~UvMission();

  /// Runs until every good set is done, or preempted; returns the machine's outcome ("done", "preempted",
  /// "aborted"). A failure at one rail set is reported for that set and the mission goes on with the next one
  /// once the robot stands on the headland floor with odometry and a map pose; otherwise the robot is stopped,
  /// its lights off, and the mission ends "aborted" with stopReason().
  std::string run();
  void requestPreempt();
  thorvald_state_machine::StateMachine& machine() { return *machine_; }
  const std::vector<RailSetReport>& reports() const { return reports_; }
  const std::set<int>& done() const { return done_; }
  /// Sets already treated (e.g. from a progress file): they are skipped.
  void markDone(const std::set<int>& indices) { done_.insert(indices.begin(), indices.end()); }
  /// Why the mission stopped before its end (empty when it did not).
  const std::string& stopReason() const { return stop_reason_; }
  /// Why the mission is holding right now (a person or obstacle in the zone, a safety stop, a relay board in
  /// doubt); empty while it is not. Any thread.
  std::string holdReason() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
  std::unique_ptr<thorvald_state_machine::StateMachine> machine_;
  std::vector<RailSetReport> reports_;
  std::set<int> done_;
  std::string stop_reason_;
  mutable std::mutex hold_mutex_;
  std::string hold_reason_;  // guarded by hold_mutex_
  friend class Impl;
};

}  // namespace greenhouse_rail_nav
