// The rail phase of the UV mission: entering the rails while the range finders watch for the floor's edge,
// backing out, the treatment with the lights on and the return to the stored pose (uv_mission_recovery.cpp: getting
// the robot back onto the headland floor, or stopping it, after a failure at a rail set or a stop on the rails).
#include <algorithm>
#include <cmath>
#include <sstream>

#include "uv_mission_impl.h"

namespace greenhouse_rail_nav {

std::string UvMission::Impl::enter(tsm::ExecutionContext& ctx) {
  ++report_.entry_attempts;
  if (!io_.odomPose(&entry_odom_)) {
    skip_reason_ = "no odometry";
    return "failed";
  }
  entry_map_known_ = io_.mapPose(&entry_map_);
  if (!entry_map_known_) log("entering without the robot's map pose: localisation will not be reset on coming back");
  rail_phase_ = true;
  entered_m_ = 0.0;
  rail_read_at_m_ = -1.0;
  MotionLimits slow = p_.motion;
  slow.max_speed_mps = p_.enter_speed_mps;
  slow.min_speed_mps = std::min(slow.min_speed_mps, 0.5 * p_.enter_speed_mps);
  OdometryMotion motion(slow);
  motion.start({MotionStep::Kind::kTranslate, p_.enter_max_distance_m, "enter"}, entry_odom_, io_.now());
  thorvald_base::Pose2D pose = entry_odom_;
  // The rail frame as seen by the last detection, carried on by odometry: rail <- odom.
  const thorvald_base::Pose2D rail_from_odom = last_obs_.robot_in_rail * entry_odom_.inverse();
  const double w0 = p_.enter_line_frequency_rps;
  double rail_seen_at_m = -1.0;  // entered_m_ when the range finders first read rail under front and wheels
  while (io_.ok()) {
    if (ctx.preemptRequested()) {
      stop();
      return tsm::kPreempted;
    }
    setZone(ZonePhase::kRow, rowEnd(entered_m_));
    const int pauses = report_.pauses;
    if (!holdWhileStopped(ctx)) return tsm::kPreempted;
    if (report_.pauses != pauses && io_.odomPose(&pose))
      motion.start({MotionStep::Kind::kTranslate, p_.enter_max_distance_m - entered_m_, "enter"}, pose, io_.now());
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
      rail_read_at_m_ = rail_seen_at_m;
      std::ostringstream o;
      o << "on the rails after " << entered_m_ << " m (rail read from " << rail_seen_at_m << " m)";
      log(o.str());
      return "on_rails";
    }
    OdometryMotion::Command c = motion.update(pose, io_.now());
    if (w0 > 0.0 && c.linear_mps > 0.0) {
      // Follow the centre line y = 0, yaw = 0 of the rail frame: critically damped for small errors.
      const thorvald_base::Pose2D r = rail_from_odom * pose;
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
  thorvald_base::Pose2D pose;
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
  thorvald_base::Pose2D pose;
  if (!io_.odomPose(&pose)) {
    skip_reason_ = "no odometry on the rails";
    return "failed";
  }
  const thorvald_base::Pose2D rail_start = pose;
  const double lights_since = io_.now();
  CruiseSpeedMeter speed;
  lit_ = LitCoverage();
  row_lit_ = RowLitCoverage(p_.rail_run, rowKnown() ? current_->rail_length_m : 0.0);
  setTreatZone(entered_m_);
  if (!holdWhileStopped(ctx)) return tsm::kPreempted;
  io_.setLights(true);
  log("UV lights on, driving along the rails");
  const std::string outcome = driveAlongRails(ctx, rail_start, lights_since, &pose, &speed);
  stop();
  io_.setLights(false);
  report_.lights_on_s = io_.now() - lights_since;
  driven_in_m_ = entered_m_ + (pose.position() - rail_start.position()).dot(rail_start.heading());
  report_.rail_length_m = driven_in_m_ - entered_m_;
  speed.stats(&report_.speed_mean_mps, &report_.speed_std_mps);
  report_.lit_pct = 100.0 * litFraction();
  treat_complete_ = outcome == "end_of_rail" && litFraction() >= p_.min_lit_fraction;
  std::ostringstream o;
  o << "UV lights off after " << report_.rail_length_m << " m on the rails (mean speed " << report_.speed_mean_mps
    << " m/s, " << report_.lit_pct << (rowKnown() ? " % of the row" : " %") << " lit)";
  log(o.str());
  if (outcome == "end_of_rail" && !treat_complete_) {
    skip_reason_ = "not every metre was lit (" + std::to_string(report_.lit_pct) + " %)";
    return "failed";
  }
  return outcome;
}

std::string UvMission::Impl::railRunFault(thorvald_base::Pose2D* pose) {
  if (surfaceStale() || !io_.odomPose(pose)) return "treatment stopped: surface readings or odometry lost on the rails";
  if (io_.surface().wheels == Surface::kEdge) return "treatment stopped: edge under a wheel on the rails";
  return "";
}

std::string UvMission::Impl::driveAlongRails(tsm::ExecutionContext& ctx, const thorvald_base::Pose2D& rail_start,
                                             double t_start, thorvald_base::Pose2D* pose, CruiseSpeedMeter* speed) {
  const double yaw_ref = rail_start.yaw;
  thorvald_base::Pose2D last = rail_start;
  double v = 0.0, t_last = t_start, along_last = 0.0;
  bool lights = true;
  while (io_.ok()) {
    if (ctx.preemptRequested()) return tsm::kPreempted;
    double along_now = (pose->position() - rail_start.position()).dot(rail_start.heading());
    addLit(along_last, along_now, litNow(lights));
    along_last = along_now;
    std::string why;
    setTreatZone(entered_m_ + along_now);
    if (mustHold(&why)) {
      v = 0.0;
      const bool lamps_were_on = lights;
      lights = false;
      if (!holdWhileStopped(ctx)) return tsm::kPreempted;
      if (io_.odomPose(pose)) {  // braked on with the lights off
        const double a = (pose->position() - rail_start.position()).dot(rail_start.heading());
        addLit(along_now, a, false);
        along_now = a;
      }
      bool preempted = false;
      if (!backToLit(ctx, along_now, lamps_were_on, &preempted)) return preempted ? tsm::kPreempted : "failed";
      if (!io_.odomPose(pose)) continue;  // railRunFault below says so
      along_last = (pose->position() - rail_start.position()).dot(rail_start.heading());
      setTreatZone(entered_m_ + along_last);
      if (mustHold(&why)) continue;
      io_.setLights(true);
      lights = true;
      last = *pose;
      t_last = io_.now();
    }
    const std::string fault = railRunFault(pose);
    if (!fault.empty()) {
      skip_reason_ = fault;
      log(skip_reason_);
      return "failed";
    }
    const double now = io_.now();
    const double dt = now - t_last;
    t_last = now;
    const double along = (pose->position() - rail_start.position()).dot(rail_start.heading());
    speed->add(std::fabs(v - p_.rail_run.treat_speed_mps) < 1e-9, (pose->position() - last.position()).norm(), dt);
    last = *pose;
    if (along > p_.rail_run.max_rail_length_m) {
      skip_reason_ = "treatment stopped: longer than max_rail_length without seeing the far wall";
      log(skip_reason_);
      return "failed";
    }
    if (inboundStep(along, dt, &v)) {
      addLit(along_last, along, litNow(lights));
      break;
    }
    io_.commandTwist(v, railSteering(yaw_ref, pose->yaw));
    io_.waitTick();
  }
  return "end_of_rail";
}

bool UvMission::Impl::inboundStep(double along, double dt, double* v) {
  const double end_range = io_.zone().end_range_m;
  if (!rowKnown()) {
    *v = inboundSpeed(p_.rail_run, *v, end_range, dt);
    // The far wall says the rail ends here (the zone's end range agrees with the set's length).
    return *v == 0.0 && along > 0.5 && end_range <= p_.rail_run.end_wall_range_m;
  }
  // The set's length known: on until the lamps have lit the row to its end, the far wall a guard.
  const double at = rowPosition(entered_m_ + along), length = current_->rail_length_m;
  *v = inboundSpeedToRowEnd(p_.rail_run, *v, at, length, end_range, dt);
  const bool guard = end_range <= p_.rail_run.wall_guard_range_m;
  if (*v != 0.0 || !(guard || at >= rowStopPosition(p_.rail_run, length) - 1e-3)) return false;
  std::ostringstream o;
  o << (guard ? "the far wall's guard stopped the robot: " : "at the row's end: ") << "base_link " << at
    << " m from the row's start of " << length << " m";
  log(o.str());
  return true;
}

UvMission::Impl::Loop UvMission::Impl::reverseToEntry(tsm::ExecutionContext& ctx, std::string* why) {
  thorvald_base::Pose2D pose;
  const double yaw_ref = entry_odom_.yaw;
  double v = 0.0, t_last = io_.now();
  const double extra_m = 0.5;  // beyond the stored pose, to find the floor if odometry came up short
  ReturnWatch watch(p_.rail_run, entry_odom_, driven_in_m_, t_last);
  while (io_.ok()) {
    if (ctx.preemptRequested()) {
      stop();
      return Loop::kPreempted;
    }
    std::string stop_why;
    // The rest of the way: back to the stored pose, where the floor ends the return; only past it (the floor not
    // sensed there yet) the rest of extra_m, where the return gives up.
    double left_m = -1.0;
    if (io_.odomPose(&pose)) {
      const double to_stored = (pose.position() - entry_odom_.position()).dot(entry_odom_.heading());
      // Back at the stored pose on the floor: done, before anything behind could hold the robot where it stops.
      if (to_stored <= 0.0 && !surfaceStale() && io_.surface().wheels == Surface::kFloor) break;
      left_m = to_stored > 0.0 ? to_stored : std::max(0.0, to_stored + extra_m);
    }
    setZone(ZonePhase::kReverse, 0.0, left_m);
    bool held = false;
    if (mustHold(&stop_why)) {
      v = 0.0;
      held = true;
      if (!holdWhileStopped(ctx)) return Loop::kPreempted;
    }
    if (surfaceStale() || !io_.odomPose(&pose)) {
      stop();
      *why = "surface readings or odometry lost";
      return Loop::kFailed;
    }
    const double now = io_.now();
    const double dt = now - t_last;
    t_last = now;
    const double along = (pose.position() - entry_odom_.position()).dot(entry_odom_.heading());
    const double reversed = driven_in_m_ - along;
    const SurfaceReading s = io_.surface();
    if (s.wheels == Surface::kEdge) {
      stop();
      *why = "edge under a wheel";
      return Loop::kEdge;
    }
    const std::string wrong = watch.update(pose, s.wheels == Surface::kRail, !held, now);
    if (!wrong.empty()) {
      stop();
      *why = wrong;
      return Loop::kFailed;
    }
    if (along <= 0.0 && s.wheels == Surface::kFloor) break;  // back at the stored pose, on the floor
    if (along < -extra_m) {
      stop();
      *why = "no floor sensed at the stored pose";
      return Loop::kFailed;
    }
    v = returnSpeed(p_.rail_run, v, reversed, driven_in_m_, dt);
    if (along <= 0.0) v = std::min(v, p_.rail_run.slow_speed_mps);
    io_.commandTwist(-v, railSteering(yaw_ref, pose.yaw));
    io_.waitTick();
  }
  stop();
  if (!io_.ok()) return Loop::kPreempted;
  if (entry_map_known_) io_.resetLocalisation(entry_map_);
  return Loop::kDone;
}

std::string UvMission::Impl::comeBack(tsm::ExecutionContext& ctx) {
  thorvald_base::Pose2D pose;
  if (!io_.odomPose(&pose)) {
    addReason("return: no odometry");
    return "failed";
  }
  log("reversing to the headland");
  std::string why;
  const Loop l = reverseToEntry(ctx, &why);
  if (l == Loop::kPreempted) return tsm::kPreempted;
  if (l != Loop::kDone) {
    addReason("return: " + why);
    log(skip_reason_);
    return "failed";
  }
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

}  // namespace greenhouse_rail_nav
