// The UV mission's machine behind UvMission: its states' bodies share the robot's interface, the current rail
// set and what was stored before entering the rails. Private to the mission library (uv_mission.cpp: selecting,
// navigating, detecting, aligning and skipping; uv_mission_rails.cpp: the rail phase; uv_mission_recovery.cpp:
// back onto the headland floor after a failure or a stop on the rails).
#pragma once

#include <algorithm>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "greenhouse_rail_nav/lit_coverage.h"
#include "greenhouse_rail_nav/uv_mission.h"

namespace greenhouse_rail_nav {

namespace tsm = thorvald_state_machine;

class UvMission::Impl {
 public:
  Impl(UvMission& owner, MissionIO& io, const UvMissionParams& p, std::vector<MissionTarget> targets)
      : owner_(owner), io_(io), p_(p), targets_(std::move(targets)), zone_hold_(p.zone.clear_time_s) {}

  // Outcomes of the motion loops.
  enum class Loop { kDone, kFailed, kPreempted, kEdge };
  // Where the robot stands after a failure at a rail set.
  enum class Safety { kSafe, kUnsafe, kPreempted };

  void build(tsm::StateMachine& sm);

 private:
  using State = std::unique_ptr<tsm::State>;
  State state(std::vector<std::string> outcomes, std::function<std::string(tsm::ExecutionContext&)> body) {
    return std::make_unique<tsm::FunctionState>(std::move(outcomes),
                                                [body](tsm::UserData&, tsm::ExecutionContext& c) { return body(c); });
  }
  void log(const std::string& s) {
    std::ostringstream o;
    o << "[rail set " << (current_ ? std::to_string(current_->index) : std::string("-")) << "] " << s;
    io_.log(o.str());
  }
  void stop() { io_.commandTwist(0.0, 0.0); }
  /// Adds a failure to the current set's reason (a treatment stopped on the rails, then its return).
  void addReason(const std::string& r) { skip_reason_ = skip_reason_.empty() ? r : skip_reason_ + "; " + r; }
  /// Holds the robot (stopped, lights off) while a person must clear a safety stop, a relay board is in doubt or the
  /// protected zone is not clear (uv_mission_safety.cpp); false when preempted meanwhile. The caller sets the zone's
  /// context first. With `behind_wait_s` > 0, a hold for something behind the robot (the rear range finders) ends after
  /// that long with *gave_up set, the zone not clear.
  bool holdWhileStopped(tsm::ExecutionContext& ctx, double behind_wait_s = 0.0, bool* gave_up = nullptr);
  /// Whether the mission must hold now, and why.
  bool mustHold(std::string* why);
  void setHoldReason(const std::string& why);
  /// `row_end_m`: ZoneContext::row_end_m (row); `reverse_left_m`: ZoneContext::reverse_left_m (reverse).
  void setZone(ZonePhase phase, double row_end_m = 0.0, double reverse_left_m = -1.0) {
    setZoneContext(phase, row_end_m, reverse_left_m);
  }
  /// The row while treating, base_link `entered_m` past the pose entering began at: the lamps are lit or about to be
  /// (ZoneContext::lamps).
  void setTreatZone(double entered_m) {
    setZoneContext(ZonePhase::kRow, rowEnd(entered_m), -1.0, true, rowKnown() ? rowPosition(entered_m) : -1.0);
  }
  void setZoneContext(ZonePhase phase, double row_end_m, double reverse_left_m, bool lamps = false,
                      double row_along_m = -1.0) {
    ZoneContext c;
    c.phase = phase;
    c.row_end_m = row_end_m;
    c.reverse_left_m = reverse_left_m;
    c.lamps = lamps;
    c.row_along_m = row_along_m;
    io_.setZoneContext(c);
  }
  /// Distance from base_link to the current set's far end when base_link is `entered_m` past the pose entering
  /// began at [m]; 0 when the set's length is unknown.
  double rowEnd(double entered_m) const;
  /// The current set's length is known (the rail-set file's `length:` or the mission's rail_length).
  bool rowKnown() const { return current_ && current_->rail_length_m > 0.0; }
  /// base_link along the current set's row from its start when `entered_m` past the pose entering began at [m].
  double rowPosition(double entered_m) const { return current_->rail_length_m - rowEnd(entered_m); }
  /// Whether the lamps shine with the lights `requested`: the relay's confirmed state when the robot reports one.
  bool litNow(bool requested) {
    bool confirmed = false;
    return requested && (!io_.lampsConfirmed(&confirmed) || confirmed);
  }
  /// Treatment: base_link moved from `from_m` to `to_m` past where treatment began with the lights `on` (lit_, and
  /// the row's share under the lamps when its length is known).
  void addLit(double from_m, double to_m, bool on) {
    lit_.add(from_m, to_m, on);
    if (rowKnown()) row_lit_.add(rowPosition(entered_m_ + from_m), rowPosition(entered_m_ + to_m), on);
  }
  /// The share of the set counted for min_lit_fraction: of its row under the lamps when its length is known, else of
  /// the rails driven.
  double litFraction() const { return rowKnown() ? row_lit_.fraction() : lit_.fraction(); }
  /// After a hold on the rails: reverse over the stretch braked through with the lights off, to the last point lit
  /// (relight_overlap_m before it); false when that failed (why in skip_reason_) or was preempted.
  bool backToLit(tsm::ExecutionContext& ctx, double along_m, bool lamps_were_on, bool* preempted);
  bool surfaceStale() {
    const SurfaceReading s = io_.surface();
    return s.stamp_s < 0.0 || io_.now() - s.stamp_s > p_.surface_timeout_s;
  }
  /// One motion step under the holds. `may_cut_short`: a reverse step held for something behind it for
  /// zone.behind_wait_s ends there, done, short of its length.
  Loop runStep(const MotionStep& step, tsm::ExecutionContext& ctx, const MotionLimits& limits,
               bool may_cut_short = false);
  bool freshObservation(double since_s, tsm::ExecutionContext& ctx, RailObservation* obs);
  double headingHold(double yaw_ref, double yaw) const {
    return std::clamp(p_.motion.heading_gain * thorvald_base::normalizeAngle(yaw_ref - yaw),
                      -p_.motion.max_turn_rate_rps, p_.motion.max_turn_rate_rps);
  }

  /// Turn rate on and off the rails: while the wheel sensors read rail the pipes guide the robot, and steering
  /// towards an odometry heading (which drifts with wheel slip) would only make the wheels fight the pipes and
  /// slip; off them the heading is held.
  double railSteering(double yaw_ref, double yaw) {
    return io_.surface().wheels == Surface::kRail ? 0.0 : headingHold(yaw_ref, yaw);
  }

  std::string select();
  std::string navigate(tsm::ExecutionContext& ctx);
  std::string detect(tsm::ExecutionContext& ctx);
  std::string search(tsm::ExecutionContext& ctx);
  std::string check();
  std::string align(tsm::ExecutionContext& ctx);
  std::string enter(tsm::ExecutionContext& ctx);
  std::string backOut(tsm::ExecutionContext& ctx);
  std::string treat(tsm::ExecutionContext& ctx);
  /// TREAT's drive along the rails from rail_start (lights on since t_start [s]) until the far wall says the rail
  /// ends ("end_of_rail"), a fault ("failed", with skip_reason_) or preemption; `pose` ends as the last odometry
  /// pose read, `speed` holds the cruise speed measured.
  std::string driveAlongRails(tsm::ExecutionContext& ctx, const thorvald_base::Pose2D& rail_start, double t_start,
                              thorvald_base::Pose2D* pose, CruiseSpeedMeter* speed);
  /// The speed `v` on the way in, `along` past where treatment began; true when stopped at the end (the row's end
  /// when its length is known, or the far wall's guard; else where the far wall says the rail ends).
  bool inboundStep(double along, double dt, double* v);
  /// Why the treatment must stop at this tick (empty: it goes on); reads the odometry pose into `pose`.
  std::string railRunFault(thorvald_base::Pose2D* pose);
  std::string comeBack(tsm::ExecutionContext& ctx);
  /// First state of every run: a robot that the last run left after it began entering a set's rails reverses to
  /// the pose stored before the entry (RETURN's motion) before anything else; "clear", "unsafe" or preempted.
  std::string resume(tsm::ExecutionContext& ctx);
  /// Reverses along the rails to the stored entry pose until the wheels read floor there (slowing after
  /// slow_fraction of driven_in_m_); kDone (localisation reset to the stored map pose), kFailed or kEdge with
  /// `why`, kPreempted.
  Loop reverseToEntry(tsm::ExecutionContext& ctx, std::string* why);
  std::string skip(tsm::ExecutionContext& ctx);
  Safety secure(tsm::ExecutionContext& ctx, std::string* note);
  Safety reverseToFloor(tsm::ExecutionContext& ctx, std::string* note);

  UvMission& owner_;
  MissionIO& io_;
  UvMissionParams p_;
  std::vector<MissionTarget> targets_;
  const MissionTarget* current_ = nullptr;
  RailSetReport report_;
  double set_start_s_ = 0.0;
  std::string skip_reason_;
  RailObservation last_obs_;
  // The pose stored before entering the rails (odometry and map) and the distance driven since.
  thorvald_base::Pose2D entry_odom_;
  thorvald_base::Pose2D entry_map_;
  bool entry_map_known_ = false;
  bool set_started_ = false;     // the robot has moved for the current set (skipping it needs a safety check)
  bool rail_phase_ = false;      // the robot has started entering the current set's rails
  bool treat_complete_ = false;  // the current set's rails were driven to their end with the lights on
  double entered_m_ = 0.0;
  /// entered_m_ when the wheel sensors (beside base_link) began to read rail for good: base_link was at the rails'
  /// start then, which places the row when the camera did not see the start (< 0: not on the rails yet).
  double rail_read_at_m_ = -1.0;
  double driven_in_m_ = 0.0;
  ZoneHold zone_hold_;
  std::string zone_why_;    // what was last in the zone
  LitCoverage lit_;         // the current set's rails lit, from where treatment began
  RowLitCoverage row_lit_;  // the current set's row under the lamps with the lights on (its length known)
};

}  // namespace greenhouse_rail_nav
