#include "greenhouse_rail_nav/uv_mission.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "uv_mission_impl.h"

namespace greenhouse_rail_nav {

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
  e << zone.validate();
  if (!(min_lit_fraction > 0.0 && min_lit_fraction <= 1.0)) e << "min_lit_fraction must be in (0, 1]; ";
  if (!(relight_overlap_m >= 0.0 && relight_overlap_m <= 1.0)) e << "relight_overlap must be in [0, 1] [m]; ";
  if (!(relight_run_up_m >= 0.0 && relight_run_up_m <= 2.0)) e << "relight_run_up must be in [0, 2] [m]; ";
  return e.str();
}

UvMission::Impl::Loop UvMission::Impl::runStep(const MotionStep& step, tsm::ExecutionContext& ctx,
                                               const MotionLimits& limits, bool may_cut_short) {
  OdometryMotion motion(limits);
  thorvald_base::Pose2D pose;
  if (!io_.odomPose(&pose)) {
    log("no odometry: cannot execute '" + step.label + "'");
    return Loop::kFailed;
  }
  motion.start(step, pose, io_.now());
  const thorvald_base::Pose2D start = pose;
  const bool translate = step.kind == MotionStep::Kind::kTranslate;
  // Reversing: the whole step is the most it still has to go (the rear range finders' hold, obstacle_zones.h).
  if (translate && step.amount < 0.0)
    setZone(ZonePhase::kReverse, 0.0, -step.amount);
  else
    setZone(ZonePhase::kHeadland);
  while (io_.ok()) {
    if (ctx.preemptRequested()) {
      stop();
      return Loop::kPreempted;
    }
    const int pauses = report_.pauses;
    const bool cut_short = may_cut_short && translate && step.amount < 0.0;
    bool gave_up = false;
    if (!holdWhileStopped(ctx, cut_short ? p_.zone.behind_wait_s : 0.0, &gave_up)) return Loop::kPreempted;
    if (gave_up) {
      stop();
      std::ostringstream o;
      o << "'" << step.label << "' ends here, " << (pose.position() - start.position()).norm() << " m of its "
        << -step.amount << " m driven";
      log(o.str());
      return Loop::kDone;
    }
    if (report_.pauses != pauses && io_.odomPose(&pose)) {
      // Held: the rest of the step from here (the motion's stall check counts from now).
      const double done = translate ? (pose.position() - start.position()).dot(start.heading())
                                    : thorvald_base::normalizeAngle(pose.yaw - start.yaw);
      motion.start({step.kind, step.amount - done, step.label}, pose, io_.now());
    }
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
  io_.wantRailDetection(true);
  while (io_.ok() && !ctx.preemptRequested() && io_.now() < deadline) {
    const RailObservation o = io_.railObservation();
    if (o.stamp_s >= since_s + p_.detect_settle_s &&
        (o.status == RailObservation::Status::kFound || o.status == RailObservation::Status::kXUnobserved)) {
      *obs = o;
      io_.wantRailDetection(false);
      return true;
    }
    stop();
    io_.waitTick();
  }
  io_.wantRailDetection(false);
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
  setZone(ZonePhase::kHeadland);
  if (!holdWhileStopped(ctx)) return tsm::kPreempted;  // a goal is sent once the zone is clear
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
      if (mustHold(&why)) {
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
  const thorvald_base::Pose2D& r = last_obs_.robot_in_rail;
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
  thorvald_base::Pose2D r = last_obs_.robot_in_rail;
  if (last_obs_.status == RailObservation::Status::kXUnobserved) {
    // The rail start is out of view, so the robot is closer than the camera can see: plan from the nearest x
    // that is seen, which makes the plan reverse far enough to see the start again.
    r.x = std::max(r.x, p_.alignment.approach_x_m + p_.alignment.x_window_m);
  }
  for (const MotionStep& step : planAlignment(r, p_.alignment)) {
    log("align: " + step.label);
    const Loop l = runStep(step, ctx, p_.motion, /*may_cut_short=*/true);
    if (l == Loop::kPreempted) return tsm::kPreempted;
    if (l != Loop::kDone) {
      skip_reason_ = "alignment motion failed";
      return "failed";
    }
  }
  return "aligned";
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
  sm.add("RESUME", state({"clear", "unsafe", P}, [this](tsm::ExecutionContext& c) { return resume(c); }),
         {{"clear", "SELECT"}, {"unsafe", "aborted"}});
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
  // A run reports what it did: sets skipped in an earlier run are tried again, treated ones stay done.
  reports_.clear();
  stop_reason_.clear();
  tsm::UserData ud;
  return machine_->run(ud);
}

void UvMission::requestPreempt() { machine_->requestPreempt(); }

}  // namespace greenhouse_rail_nav
