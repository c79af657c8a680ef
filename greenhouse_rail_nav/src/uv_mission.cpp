#include "greenhouse_rail_nav/uv_mission.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace greenhouse_rail_nav {

namespace tsm = thorvald_state_machine;

std::string UvMissionParams::validate() const {
  std::ostringstream e;
  e << alignment.validate() << motion.validate() << rail_run.validate();
  if (!(nav_timeout_s > 0.0)) e << "nav_timeout must be > 0 [s]; ";
  if (nav_attempts < 1) e << "nav_attempts must be >= 1; ";
  if (!(detect_timeout_s > 0.0)) e << "detect_timeout must be > 0 [s]; ";
  if (!(detect_settle_s >= 0.0 && detect_settle_s < detect_timeout_s))
    e << "detect_settle must be in [0, detect_timeout); ";
  if (!(search_step_rad > 0.0 && search_limit_rad >= search_step_rad && search_limit_rad <= M_PI))
    e << "search_step must be > 0 and <= search_limit <= pi [rad]; ";
  if (max_align_attempts < 1) e << "max_align_attempts must be >= 1; ";
  if (!(enter_speed_mps > 0.0 && enter_speed_mps <= 0.3)) e << "enter_speed must be in (0, 0.3] [m/s]; ";
  if (!(enter_max_distance_m > 0.0)) e << "enter_max_distance must be > 0 [m]; ";
  if (!(enter_line_frequency_rps >= 0.0 && enter_line_frequency_rps <= 3.0))
    e << "enter_line_frequency must be in [0, 3] [rad/s]; ";
  if (!(surface_timeout_s > 0.0)) e << "surface_timeout must be > 0 [s]; ";
  if (!(on_rails_margin_m >= 0.0 && on_rails_margin_m < enter_max_distance_m))
    e << "on_rails_margin must be in [0, enter_max_distance) [m]; ";
  if (!(secure_wait_s > 0.0)) e << "secure_wait must be > 0 [s]; ";
  if (!(recover_reverse_max_m >= 0.0 && recover_reverse_max_m <= 5.0))
    e << "recover_reverse_max must be in [0, 5] [m]; ";
  return e.str();
}

class UvMission::Impl {
 public:
  Impl(UvMission& owner, MissionIO& io, const UvMissionParams& p, std::vector<MissionTarget> targets)
      : owner_(owner), io_(io), p_(p), targets_(std::move(targets)) {}

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
  /// Holds the robot while a person must clear a safety stop; false when preempted meanwhile.
  bool holdWhileStopped(tsm::ExecutionContext& ctx);
  bool surfaceStale() {
    const SurfaceReading s = io_.surface();
    return s.stamp_s < 0.0 || io_.now() - s.stamp_s > p_.surface_timeout_s;
  }
  Loop runStep(const MotionStep& step, tsm::ExecutionContext& ctx, const MotionLimits& limits);
  bool freshObservation(double since_s, tsm::ExecutionContext& ctx, RailObservation* obs);
  double headingHold(double yaw_ref, double yaw) const {
    return std::clamp(p_.motion.heading_gain * normalizeAngle(yaw_ref - yaw), -p_.motion.max_turn_rate_rps,
                      p_.motion.max_turn_rate_rps);
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
  std::string comeBack(tsm::ExecutionContext& ctx);
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
  Pose2D entry_odom_;
  Pose2D entry_map_;
  bool entry_map_known_ = false;
  bool set_started_ = false;     // the robot has moved for the current set (skipping it needs a safety check)
  bool rail_phase_ = false;      // the robot has started entering the current set's rails
  bool treat_complete_ = false;  // the current set's rails were driven to their end with the lights on
  double entered_m_ = 0.0;
  double driven_in_m_ = 0.0;
};

bool UvMission::Impl::holdWhileStopped(tsm::ExecutionContext& ctx) {
  std::string why;
  if (!io_.safetyStopped(&why)) return true;
  stop();
  io_.setLights(false);
  log("paused: " + why + " (a person must clear it)");
  while (io_.ok() && io_.safetyStopped(&why)) {
    if (ctx.preemptRequested()) return false;
    stop();
    io_.waitTick();
  }
  log("safety stop cleared, continuing");
  return io_.ok();
}

UvMission::Impl::Loop UvMission::Impl::runStep(const MotionStep& step, tsm::ExecutionContext& ctx,
                                               const MotionLimits& limits) {
  OdometryMotion motion(limits);
  Pose2D pose;
  if (!io_.odomPose(&pose)) {
    log("no odometry: cannot execute '" + step.label + "'");
    return Loop::kFailed;
  }
  motion.start(step, pose, io_.now());
  while (io_.ok()) {
    if (ctx.preemptRequested()) {
      stop();
      return Loop::kPreempted;
    }
    if (!holdWhileStopped(ctx)) return Loop::kPreempted;
    if (surfaceStale()) {
      stop();
      log("surface readings are stale: stopping '" + step.label + "'");
      return Loop::kFailed;
    }
    if (io_.surface().wheels == Surface::kEdge) {
      stop();
      log("edge under a wheel during '" + step.label + "': stopped");
      return Loop::kEdge;
    }
    if (!io_.odomPose(&pose)) {
      stop();
      log("odometry lost during '" + step.label + "'");
      return Loop::kFailed;
    }
    const OdometryMotion::Command c = motion.update(pose, io_.now());
    io_.commandTwist(c.linear_mps, c.angular_rps);
    if (c.failed) {
      log("'" + step.label + "' failed: " + c.reason);
      return Loop::kFailed;
    }
    if (c.done) return Loop::kDone;
    io_.waitTick();
  }
  stop();
  return Loop::kPreempted;
}

bool UvMission::Impl::freshObservation(double since_s, tsm::ExecutionContext& ctx, RailObservation* obs) {
  const double deadline = io_.now() + p_.detect_timeout_s;
  while (io_.ok() && !ctx.preemptRequested() && io_.now() < deadline) {
    const RailObservation o = io_.railObservation();
    if (o.stamp_s >= since_s + p_.detect_settle_s &&
        (o.status == RailObservation::Status::kFound || o.status == RailObservation::Status::kXUnobserved)) {
      *obs = o;
      return true;
    }
    stop();
    io_.waitTick();
  }
  return false;
}

std::string UvMission::Impl::select() {
  for (const MissionTarget& t : targets_) {
    if (owner_.done_.count(t.index)) continue;
    bool reported = false;
    for (const auto& r : owner_.reports_) reported = reported || (r.index == t.index && !r.treated);
    if (reported) continue;  // tried in this run and skipped
    set_started_ = rail_phase_ = treat_complete_ = false;
    if (!t.good) {
      current_ = &t;
      skip_reason_ = "marked uncertain by the map analyzer: " + t.note;
      report_ = RailSetReport();
      report_.index = t.index;
      set_start_s_ = io_.now();
      return "skip";
    }
    current_ = &t;
    report_ = RailSetReport();
    report_.index = t.index;
    set_start_s_ = io_.now();
    std::ostringstream s;
    s << "next: target pose (" << t.target_pose.x << ", " << t.target_pose.y << ", " << t.target_pose.yaw << ")";
    log(s.str());
    return "next";
  }
  current_ = nullptr;
  return "finished";
}

std::string UvMission::Impl::navigate(tsm::ExecutionContext& ctx) {
  set_started_ = true;
  for (int attempt = 1; attempt <= p_.nav_attempts; ++attempt) {
    io_.sendNavGoal(current_->target_pose);
    const double deadline = io_.now() + p_.nav_timeout_s;
    std::string reason;
    NavState st = NavState::kActive;
    while (io_.ok()) {
      if (ctx.preemptRequested()) {
        io_.cancelNav();
        return tsm::kPreempted;
      }
      std::string why;
      if (io_.safetyStopped(&why)) {
        io_.cancelNav();
        if (!holdWhileStopped(ctx)) return tsm::kPreempted;
        io_.sendNavGoal(current_->target_pose);
      }
      st = io_.navState(&reason);
      if (st == NavState::kSucceeded || st == NavState::kFailed) break;
      if (io_.now() > deadline) {
        io_.cancelNav();
        reason = "timed out";
        st = NavState::kFailed;
        break;
      }
      io_.waitTick();
    }
    if (st == NavState::kSucceeded) {
      log("arrived at the target pose");
      return "arrived";
    }
    std::ostringstream s;
    s << "navigation attempt " << attempt << " failed: " << reason;
    log(s.str());
  }
  skip_reason_ = "navigation to the target pose failed";
  return "failed";
}

std::string UvMission::Impl::detect(tsm::ExecutionContext& ctx) {
  stop();
  if (freshObservation(io_.now(), ctx, &last_obs_)) return "found";
  if (ctx.preemptRequested()) return tsm::kPreempted;
  log("rails not seen from here");
  return "not_found";
}

std::string UvMission::Impl::search(tsm::ExecutionContext& ctx) {
  ++report_.searches;
  const auto rotations = railSearchRotations(p_.search_step_rad, p_.search_limit_rad);
  for (std::size_t i = 0; i < rotations.size(); ++i) {
    std::ostringstream label;
    label << "search rotation " << (i + 1) << "/" << rotations.size();
    const Loop l = runStep({MotionStep::Kind::kRotate, rotations[i], label.str()}, ctx, p_.motion);
    if (l == Loop::kPreempted) return tsm::kPreempted;
    if (l != Loop::kDone) break;
    if (freshObservation(io_.now(), ctx, &last_obs_)) {
      log("rails found by searching");
      return "found";
    }
  }
  skip_reason_ = "rails not found by the search";
  return "not_found";
}

std::string UvMission::Impl::check() {
  const bool x_observed = last_obs_.status == RailObservation::Status::kFound;
  const Pose2D& r = last_obs_.robot_in_rail;
  std::ostringstream s;
  s << "pose in the rail frame x " << r.x << (x_observed ? "" : " (unobserved)") << ", y " << r.y << ", yaw " << r.yaw;
  if (withinEntryLimits(r, x_observed, p_.alignment)) {
    log(s.str() + ": within the limits, entering");
    return "within";
  }
  if (report_.align_attempts >= p_.max_align_attempts) {
    skip_reason_ = "still outside the limits after " + std::to_string(report_.align_attempts) + " alignments";
    log(s.str() + ": " + skip_reason_);
    return "give_up";
  }
  log(s.str() + ": outside the limits, aligning");
  return "outside";
}

std::string UvMission::Impl::align(tsm::ExecutionContext& ctx) {
  ++report_.align_attempts;
  Pose2D r = last_obs_.robot_in_rail;
  if (last_obs_.status == RailObservation::Status::kXUnobserved) {
    // The rail start is out of view, so the robot is closer than the camera can see: plan from the nearest x
    // that is seen, which makes the plan reverse far enough to see the start again.
    r.x = std::max(r.x, p_.alignment.approach_x_m + p_.alignment.x_window_m);
  }
  for (const MotionStep& step : planAlignment(r, p_.alignment)) {
    log("align: " + step.label);
    const Loop l = runStep(step, ctx, p_.motion);
    if (l == Loop::kPreempted) return tsm::kPreempted;
    if (l != Loop::kDone) {
      skip_reason_ = "alignment motion failed";
      return "failed";
    }
  }
  return "aligned";
}

std::string UvMission::Impl::enter(tsm::ExecutionContext& ctx) {
  ++report_.entry_attempts;
  if (!io_.odomPose(&entry_odom_)) {
    skip_reason_ = "no odometry";
    return "failed";
  }
  entry_map_known_ = io_.mapPose(&entry_map_);
  rail_phase_ = true;
  entered_m_ = 0.0;
  MotionLimits slow = p_.motion;
  slow.max_speed_mps = p_.enter_speed_mps;
  slow.min_speed_mps = std::min(slow.min_speed_mps, 0.5 * p_.enter_speed_mps);
  OdometryMotion motion(slow);
  motion.start({MotionStep::Kind::kTranslate, p_.enter_max_distance_m, "enter"}, entry_odom_, io_.now());
  Pose2D pose = entry_odom_;
  // The rail frame as seen by the last detection, carried on by odometry: rail <- odom.
  const Pose2D rail_from_odom = last_obs_.robot_in_rail.compose(entry_odom_.inverse());
  const double w0 = p_.enter_line_frequency_rps;
  double rail_seen_at_m = -1.0;  // entered_m_ when the range finders first read rail under front and wheels
  while (io_.ok()) {
    if (ctx.preemptRequested()) {
      stop();
      return tsm::kPreempted;
    }
    if (!holdWhileStopped(ctx)) return tsm::kPreempted;
    if (surfaceStale() || !io_.odomPose(&pose)) {
      stop();
      log("entering: surface readings or odometry lost, backing out");
      return "failed";
    }
    entered_m_ = (pose.position() - entry_odom_.position()).dot(entry_odom_.heading());
    const SurfaceReading s = io_.surface();
    if (s.front == Surface::kEdge || s.wheels == Surface::kEdge) {
      stop();
      std::ostringstream o;
      o << "entering: the floor's edge in front of a rail wheel after " << entered_m_ << " m, backing out";
      log(o.str());
      return "edge";
    }
    // The wheel sensors' cones see a pipe a few centimetres before the rail wheels are carried by it: drive on
    // on_rails_margin with rail read throughout before calling it on the rails.
    if (s.front == Surface::kRail && s.wheels == Surface::kRail) {
      if (rail_seen_at_m < 0.0) rail_seen_at_m = entered_m_;
    } else {
      rail_seen_at_m = -1.0;
    }
    if (rail_seen_at_m >= 0.0 && entered_m_ - rail_seen_at_m >= p_.on_rails_margin_m) {
      stop();
      std::ostringstream o;
      o << "on the rails after " << entered_m_ << " m (rail read from " << rail_seen_at_m << " m)";
      log(o.str());
      return "on_rails";
    }
    OdometryMotion::Command c = motion.update(pose, io_.now());
    if (w0 > 0.0 && c.linear_mps > 0.0) {
      // Follow the centre line y = 0, yaw = 0 of the rail frame: critically damped for small errors.
      const Pose2D r = rail_from_odom.compose(pose);
      c.angular_rps = std::clamp(-2.0 * w0 * r.yaw - w0 * w0 * r.y / std::max(c.linear_mps, 0.02),
                                 -p_.motion.max_turn_rate_rps, p_.motion.max_turn_rate_rps);
    }
    io_.commandTwist(c.linear_mps, c.angular_rps);
    if (c.done || c.failed) {
      stop();
      log("entering: the rails were not reached within the entry distance, backing out");
      return "failed";
    }
    io_.waitTick();
  }
  stop();
  return tsm::kPreempted;
}

std::string UvMission::Impl::backOut(tsm::ExecutionContext& ctx) {
  Pose2D pose;
  double back = entered_m_;
  if (io_.odomPose(&pose)) back = (pose.position() - entry_odom_.position()).dot(entry_odom_.heading());
  // The edge check stays on while backing out: the wheels must not leave the floor backwards either, but a
  // front sensor over the edge is expected here.
  const Loop l = runStep({MotionStep::Kind::kTranslate, -back, "back out"}, ctx, p_.motion);
  if (l == Loop::kPreempted) return tsm::kPreempted;
  if (l != Loop::kDone) {
    skip_reason_ = "backing out failed";
    return "failed";
  }
  if (report_.entry_attempts >= p_.max_align_attempts) {
    skip_reason_ = "entering failed " + std::to_string(report_.entry_attempts) + " times";
    return "give_up";
  }
  return "backed_out";
}

std::string UvMission::Impl::treat(tsm::ExecutionContext& ctx) {
  Pose2D pose, last;
  if (!io_.odomPose(&pose)) {
    skip_reason_ = "no odometry on the rails";
    return "failed";
  }
  last = pose;
  const double yaw_ref = pose.yaw;
  const Pose2D rail_start = pose;
  double v = 0.0, t_last = io_.now(), lights_since = t_last;
  double sum = 0.0, sum2 = 0.0;
  int n = 0;
  io_.setLights(true);
  log("UV lights on, driving along the rails");
  std::string outcome = "end_of_rail";
  while (io_.ok()) {
    if (ctx.preemptRequested()) {
      outcome = tsm::kPreempted;
      break;
    }
    std::string why;
    if (io_.safetyStopped(&why)) {
      v = 0.0;
      if (!holdWhileStopped(ctx)) {
        outcome = tsm::kPreempted;
        break;
      }
      io_.setLights(true);
    }
    if (surfaceStale() || !io_.odomPose(&pose)) {
      skip_reason_ = "treatment stopped: surface readings or odometry lost on the rails";
      log(skip_reason_);
      outcome = "failed";
      break;
    }
    if (io_.surface().wheels == Surface::kEdge) {
      skip_reason_ = "treatment stopped: edge under a wheel on the rails";
      log(skip_reason_);
      outcome = "failed";
      break;
    }
    const double now = io_.now();
    const double dt = now - t_last;
    t_last = now;
    const double along = (pose.position() - rail_start.position()).dot(rail_start.heading());
    if (dt > 0.0 && std::fabs(v - p_.rail_run.treat_speed_mps) < 1e-9) {
      const double speed = (pose.position() - last.position()).norm() / dt;
      sum += speed;
      sum2 += speed * speed;
      ++n;
    }
    last = pose;
    if (along > p_.rail_run.max_rail_length_m) {
      skip_reason_ = "treatment stopped: longer than max_rail_length without seeing the far wall";
      log(skip_reason_);
      outcome = "failed";
      break;
    }
    v = inboundSpeed(p_.rail_run, v, io_.forwardRange(), dt);
    if (v == 0.0 && along > 0.5) break;  // the far wall says the rail ends here
    io_.commandTwist(v, railSteering(yaw_ref, pose.yaw));
    io_.waitTick();
  }
  stop();
  io_.setLights(false);
  report_.lights_on_s = io_.now() - lights_since;
  driven_in_m_ = entered_m_ + (pose.position() - rail_start.position()).dot(rail_start.heading());
  report_.rail_length_m = driven_in_m_ - entered_m_;
  if (n > 0) {
    report_.speed_mean_mps = sum / n;
    report_.speed_std_mps = std::sqrt(std::max(0.0, sum2 / n - report_.speed_mean_mps * report_.speed_mean_mps));
  }
  treat_complete_ = outcome == "end_of_rail";
  std::ostringstream o;
  o << "UV lights off after " << report_.rail_length_m << " m on the rails (mean speed " << report_.speed_mean_mps
    << " m/s)";
  log(o.str());
  return outcome;
}

std::string UvMission::Impl::comeBack(tsm::ExecutionContext& ctx) {
  Pose2D pose;
  if (!io_.odomPose(&pose)) {
    addReason("return: no odometry");
    return "failed";
  }
  const double yaw_ref = entry_odom_.yaw;
  double v = 0.0, t_last = io_.now();
  const double extra_m = 0.5;  // beyond the stored pose, to find the floor if odometry came up short
  log("reversing to the headland");
  while (io_.ok()) {
    if (ctx.preemptRequested()) {
      stop();
      return tsm::kPreempted;
    }
    std::string why;
    if (io_.safetyStopped(&why)) {
      v = 0.0;
      if (!holdWhileStopped(ctx)) return tsm::kPreempted;
    }
    if (surfaceStale() || !io_.odomPose(&pose)) {
      stop();
      addReason("return: surface readings or odometry lost");
      log(skip_reason_);
      return "failed";
    }
    const double now = io_.now();
    const double dt = now - t_last;
    t_last = now;
    const double along = (pose.position() - entry_odom_.position()).dot(entry_odom_.heading());
    const double reversed = driven_in_m_ - along;
    const SurfaceReading s = io_.surface();
    if (s.wheels == Surface::kEdge) {
      stop();
      addReason("return: edge under a wheel");
      log(skip_reason_);
      return "failed";
    }
    if (along <= 0.0 && s.wheels == Surface::kFloor) break;  // back at the stored pose, on the floor
    if (along < -extra_m) {
      stop();
      addReason("return: no floor sensed at the stored pose");
      log(skip_reason_);
      return "failed";
    }
    v = returnSpeed(p_.rail_run, v, reversed, driven_in_m_, dt);
    if (along <= 0.0) v = std::min(v, p_.rail_run.slow_speed_mps);
    io_.commandTwist(-v, railSteering(yaw_ref, pose.yaw));
    io_.waitTick();
  }
  stop();
  if (entry_map_known_) io_.resetLocalisation(entry_map_);
  if (!treat_complete_) {
    log("back on the headland floor; the rails were not treated to their end");
    return "back_untreated";
  }
  report_.treated = true;
  report_.result = "treated";
  report_.duration_s = io_.now() - set_start_s_;
  owner_.reports_.push_back(report_);
  owner_.done_.insert(current_->index);
  log("back on the headland floor; rail set treated");
  return "back";
}

UvMission::Impl::Safety UvMission::Impl::reverseToFloor(tsm::ExecutionContext& ctx, std::string* note) {
  Pose2D start, pose;
  if (!io_.odomPose(&start)) {
    *note = "rail under the wheels and no odometry to reverse on";
    return Safety::kUnsafe;
  }
  std::ostringstream l;
  l << "rail under the wheels: reversing at " << p_.rail_run.slow_speed_mps << " m/s to find the floor (at most "
    << p_.recover_reverse_max_m << " m)";
  log(l.str());
  pose = start;
  while (io_.ok()) {
    if (ctx.preemptRequested()) {
      stop();
      return Safety::kPreempted;
    }
    if (!holdWhileStopped(ctx)) return Safety::kPreempted;
    if (surfaceStale() || !io_.odomPose(&pose)) {
      stop();
      *note = "surface readings or odometry lost while reversing to the floor";
      return Safety::kUnsafe;
    }
    const double reversed = (pose.position() - start.position()).norm();
    const SurfaceReading s = io_.surface();
    if (s.wheels == Surface::kEdge) {
      stop();
      *note = "an edge under a wheel while reversing to the floor";
      return Safety::kUnsafe;
    }
    if (s.wheels == Surface::kFloor) {
      stop();
      if (entry_map_known_) io_.resetLocalisation(entry_map_);
      std::ostringstream o;
      o << "floor found after reversing " << reversed << " m more";
      *note = o.str();
      return Safety::kSafe;
    }
    if (reversed > p_.recover_reverse_max_m) {
      stop();
      std::ostringstream o;
      o << "still on the rails after reversing " << reversed << " m more";
      *note = o.str();
      return Safety::kUnsafe;
    }
    io_.commandTwist(-p_.rail_run.slow_speed_mps, railSteering(entry_odom_.yaw, pose.yaw));
    io_.waitTick();
  }
  stop();
  return Safety::kPreempted;
}

UvMission::Impl::Safety UvMission::Impl::secure(tsm::ExecutionContext& ctx, std::string* note) {
  // The surface classifier needs a few agreeing readings after a change: wait for a fresh, decided reading.
  const double deadline = io_.now() + p_.secure_wait_s;
  SurfaceReading s;
  while (true) {
    if (!io_.ok() || ctx.preemptRequested()) return Safety::kPreempted;
    if (!holdWhileStopped(ctx)) return Safety::kPreempted;
    stop();
    s = io_.surface();
    const bool fresh = !surfaceStale();
    if (fresh && s.wheels != Surface::kUnknown) break;
    if (io_.now() >= deadline) {
      *note = fresh ? "the range finders at the wheels read neither floor nor rail under both wheels"
                    : "no fresh readings from the range finders";
      return Safety::kUnsafe;
    }
    io_.waitTick();
  }
  if (s.wheels == Surface::kEdge) {
    *note = "an edge under a wheel";
    return Safety::kUnsafe;
  }
  if (s.wheels == Surface::kRail) {
    if (!rail_phase_) {
      *note = "rail under the wheels away from the rails' entry";
      return Safety::kUnsafe;
    }
    const Safety r = reverseToFloor(ctx, note);
    if (r != Safety::kSafe) return r;
  }
  Pose2D pose;
  if (!io_.odomPose(&pose)) {
    *note = "no odometry";
    return Safety::kUnsafe;
  }
  const double map_deadline = io_.now() + p_.detect_timeout_s;
  while (!io_.mapPose(&pose)) {
    if (!io_.ok() || ctx.preemptRequested()) return Safety::kPreempted;
    if (io_.now() >= map_deadline) {
      *note = "the robot's pose in the map is unknown";
      return Safety::kUnsafe;
    }
    stop();
    io_.waitTick();
  }
  return Safety::kSafe;
}

std::string UvMission::Impl::skip(tsm::ExecutionContext& ctx) {
  stop();
  io_.setLights(false);
  const std::string reason = skip_reason_.empty() ? "skipped" : skip_reason_;
  skip_reason_.clear();
  std::string note;
  Safety safety = Safety::kSafe;
  if (set_started_) {
    safety = secure(ctx, &note);
    if (safety == Safety::kPreempted) {
      stop();
      return tsm::kPreempted;
    }
  }
  // The lights went over the whole rails even if the way back needed help: the set is treated.
  report_.treated = treat_complete_;
  report_.result = treat_complete_ ? "treated; " + reason : reason;
  if (!note.empty()) report_.result += safety == Safety::kSafe ? " (" + note + ")" : "; robot stopped: " + note;
  report_.duration_s = io_.now() - set_start_s_;
  owner_.reports_.push_back(report_);
  if (treat_complete_) owner_.done_.insert(current_->index);
  if (safety != Safety::kSafe) {
    stop();
    owner_.stop_reason_ = "rail set " + std::to_string(current_->index) + ": " + reason + "; robot stopped: " + note;
    log("mission stopped, not safe to go on: " + note);
    return "unsafe";
  }
  log((treat_complete_ ? "treated, with a failure: " : "skipped: ") + report_.result);
  return "next";
}

void UvMission::Impl::build(tsm::StateMachine& sm) {
  const std::string P = tsm::kPreempted;
  sm.add("SELECT", state({"next", "skip", "finished"}, [this](tsm::ExecutionContext&) { return select(); }),
         {{"next", "NAVIGATE"}, {"skip", "SKIP"}, {"finished", "done"}});
  sm.add("NAVIGATE", state({"arrived", "failed", P}, [this](tsm::ExecutionContext& c) { return navigate(c); }),
         {{"arrived", "DETECT"}, {"failed", "SKIP"}});
  sm.add("DETECT", state({"found", "not_found", P}, [this](tsm::ExecutionContext& c) { return detect(c); }),
         {{"found", "CHECK"}, {"not_found", "SEARCH"}});
  sm.add("SEARCH", state({"found", "not_found", P}, [this](tsm::ExecutionContext& c) { return search(c); }),
         {{"found", "CHECK"}, {"not_found", "SKIP"}});
  sm.add("CHECK", state({"within", "outside", "give_up"}, [this](tsm::ExecutionContext&) { return check(); }),
         {{"within", "ENTER"}, {"outside", "ALIGN"}, {"give_up", "SKIP"}});
  sm.add("ALIGN", state({"aligned", "failed", P}, [this](tsm::ExecutionContext& c) { return align(c); }),
         {{"aligned", "DETECT"}, {"failed", "SKIP"}});
  sm.add("ENTER", state({"on_rails", "edge", "failed", P}, [this](tsm::ExecutionContext& c) { return enter(c); }),
         {{"on_rails", "TREAT"}, {"edge", "BACK_OUT"}, {"failed", "BACK_OUT"}});
  sm.add("BACK_OUT",
         state({"backed_out", "give_up", "failed", P}, [this](tsm::ExecutionContext& c) { return backOut(c); }),
         {{"backed_out", "DETECT"}, {"give_up", "SKIP"}, {"failed", "SKIP"}});
  sm.add("TREAT", state({"end_of_rail", "failed", P}, [this](tsm::ExecutionContext& c) { return treat(c); }),
         {{"end_of_rail", "RETURN"}, {"failed", "RETURN"}});
  sm.add("RETURN",
         state({"back", "back_untreated", "failed", P}, [this](tsm::ExecutionContext& c) { return comeBack(c); }),
         {{"back", "SELECT"}, {"back_untreated", "SKIP"}, {"failed", "SKIP"}});
  // Every failure at a rail set comes here: the robot is stopped, lights off, and the mission goes on only when
  // it stands on the headland floor with odometry and a map pose.
  sm.add("SKIP", state({"next", "unsafe", P}, [this](tsm::ExecutionContext& c) { return skip(c); }),
         {{"next", "SELECT"}, {"unsafe", "aborted"}});
}

UvMission::UvMission(MissionIO& io, const UvMissionParams& params, std::vector<MissionTarget> targets)
    : impl_(std::make_unique<Impl>(*this, io, params, std::move(targets))),
      machine_(std::make_unique<tsm::StateMachine>("uv_mission", std::vector<std::string>{"done", "aborted"}, 64)) {
  const std::string problems = params.validate();
  if (!problems.empty()) throw std::invalid_argument("uv_mission parameters: " + problems);
  impl_->build(*machine_);
  machine_->setClock([&io] { return io.now(); });
}

UvMission::~UvMission() = default;

std::string UvMission::run() {
  tsm::UserData ud;
  return machine_->run(ud);
}

void UvMission::requestPreempt() { machine_->requestPreempt(); }

}  // namespace greenhouse_rail_nav
