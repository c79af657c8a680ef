// Getting the UV mission's robot back onto the headland floor, or stopping it, when a run begins after an earlier
// one stopped on the rails (RESUME) and after a failure at a rail set (SKIP): the robot must stand on the floor with
// odometry and a map pose before any navigation goal is sent.
#include <algorithm>
#include <sstream>

#include "uv_mission_impl.h"

namespace greenhouse_rail_nav {

std::string UvMission::Impl::resume(tsm::ExecutionContext& ctx) {
  if (!rail_phase_) return "clear";  // the last run did not stop after entering a set's rails
  // The last run was stopped (preempted or aborted) after the robot began to enter a set's rails: it may stand on
  // them, and no navigation goal may be sent from there. Wait for a fresh, decided reading at the wheels.
  const double deadline = io_.now() + p_.secure_wait_s;
  while (surfaceStale() || io_.surface().wheels == Surface::kUnknown) {
    if (!io_.ok() || ctx.preemptRequested()) return tsm::kPreempted;
    if (io_.now() >= deadline) {
      owner_.stop_reason_ =
          "resuming after a stop at the rails: no fresh, decided reading of the range finders "
          "at the wheels";
      log(owner_.stop_reason_);
      return "unsafe";
    }
    stop();
    io_.waitTick();
  }
  const Surface wheels = io_.surface().wheels;
  if (wheels == Surface::kEdge) {
    owner_.stop_reason_ = "resuming after a stop at the rails: an edge under a wheel";
    log(owner_.stop_reason_);
    return "unsafe";
  }
  if (wheels == Surface::kRail) {
    thorvald_base::Pose2D pose;
    if (!io_.odomPose(&pose)) {
      owner_.stop_reason_ = "resuming on the rails: no odometry to reverse on";
      log(owner_.stop_reason_);
      return "unsafe";
    }
    driven_in_m_ = std::max(0.0, (pose.position() - entry_odom_.position()).dot(entry_odom_.heading()));
    std::ostringstream l;
    l << "resuming: the last run stopped on the rails, " << driven_in_m_
      << " m from the stored pose; reversing to it before anything else";
    log(l.str());
    std::string why;
    const Loop r = reverseToEntry(ctx, &why);
    if (r == Loop::kPreempted) return tsm::kPreempted;
    if (r != Loop::kDone) {
      owner_.stop_reason_ = "resuming on the rails: " + why;
      log(owner_.stop_reason_);
      return "unsafe";
    }
    log("resuming: back on the headland floor at the stored pose");
  }
  rail_phase_ = false;
  return "clear";
}

UvMission::Impl::Safety UvMission::Impl::reverseToFloor(tsm::ExecutionContext& ctx, std::string* note) {
  thorvald_base::Pose2D start, pose;
  if (!io_.odomPose(&start)) {
    *note = "rail under the wheels and no odometry to reverse on";
    return Safety::kUnsafe;
  }
  std::ostringstream l;
  l << "rail under the wheels: reversing at " << p_.rail_run.slow_speed_mps << " m/s to find the floor (at most "
    << p_.recover_reverse_max_m << " m)";
  log(l.str());
  pose = start;
  setZone(ZonePhase::kReverse);
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
  thorvald_base::Pose2D pose;
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

}  // namespace greenhouse_rail_nav
