// The UV mission's holds: a safety stop a person must clear (the bumper), a relay board whose outputs are in doubt,
// and the protected zone (obstacle_zones.h: a person or an obstacle near the robot, in the row ahead or behind it
// while reversing). While holding, the robot stands with its lights off; on the rails it then comes back over the
// stretch it braked through with the lights off before they go on again.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "uv_mission_impl.h"

namespace greenhouse_rail_nav {

namespace {
constexpr double kHoldNoteS = 30.0;  // a long hold is logged again this often [s]
}  // namespace

std::string UvMission::holdReason() const {
  std::lock_guard<std::mutex> l(hold_mutex_);
  return hold_reason_;
}

void UvMission::Impl::setHoldReason(const std::string& why) {
  std::lock_guard<std::mutex> l(owner_.hold_mutex_);
  owner_.hold_reason_ = why;
}

bool UvMission::Impl::mustHold(std::string* why) {
  if (io_.safetyStopped(why)) {
    *why += " (a person must clear it)";
    return true;
  }
  if (io_.lightsInDoubt(why)) {
    *why = "the lamps' relay board is in doubt: " + *why;
    return true;
  }
  const ZoneVerdict v = io_.zone();
  if (v.blocked) zone_why_ = v.why;
  if (!zone_hold_.update(v.blocked, io_.now())) return false;
  std::ostringstream o;
  o << zone_why_;
  if (!v.blocked) o << "; clear, going on after " << p_.zone.clear_time_s << " s";
  *why = o.str();
  return true;
}

bool UvMission::Impl::holdWhileStopped(tsm::ExecutionContext& ctx, double behind_wait_s, bool* gave_up) {
  if (gave_up) *gave_up = false;
  std::string why;
  if (!mustHold(&why)) return true;
  stop();
  io_.setLights(false);
  ++report_.pauses;
  log("paused: " + why);
  setHoldReason(why);
  // A hold lasts as long as the zone is not clear, also for a stationary obstacle that is no person: say so
  // periodically, with what it waits for and where.
  const double since = io_.now();
  double next_note = since + kHoldNoteS;
  while (io_.ok() && mustHold(&why)) {
    if (behind_wait_s > 0.0 && gave_up && io_.zone().behind && io_.now() - since >= behind_wait_s) {
      std::ostringstream o;
      o << "held " << std::lround(io_.now() - since) << " s for something behind: " << why;
      log(o.str());
      setHoldReason("");
      *gave_up = true;
      return true;
    }
    if (ctx.preemptRequested()) {
      setHoldReason("");
      return false;
    }
    stop();
    setHoldReason(why);
    if (io_.now() >= next_note) {
      std::ostringstream o;
      o << "still paused after " << std::lround(io_.now() - since) << " s: " << why;
      log(o.str());
      next_note += kHoldNoteS;
    }
    io_.waitTick();
  }
  setHoldReason("");
  log("clear, continuing");
  return io_.ok();
}

double UvMission::Impl::rowEnd(double entered_m) const {
  if (!current_ || !(current_->rail_length_m > 0.0)) return 0.0;
  // base_link in the rail frame when entering began, from the last detection. With the rail start out of the
  // camera's view: where the wheel sensors began to read rail (base_link at the rails' start then), or before that
  // at least the nearest x the camera sees. Taking the nearest x on the rails too ended the treatment 0.35 m short of
  // the row's end, and counted the row lit all the same (thorvald_sim, the demo's 2-set house).
  double x0 = last_obs_.robot_in_rail.x;
  if (last_obs_.status == RailObservation::Status::kXUnobserved)
    x0 = rail_read_at_m_ >= 0.0 ? -rail_read_at_m_ : std::max(x0, p_.alignment.approach_x_m + p_.alignment.x_window_m);
  return std::max(1e-3, current_->rail_length_m - (x0 + entered_m));
}

bool UvMission::Impl::backToLit(tsm::ExecutionContext& ctx, double along_m, bool lamps_were_on, bool* preempted) {
  *preempted = false;
  const double unlit = std::max(0.0, along_m - lit_.litUpTo());
  // The stretch under the lamps when they went off got part of its dose: they must come on again (after the run-up to
  // the treatment speed) behind it, not where the robot stopped.
  // Never back past where the treatment began (on the rails, the lamps' first lit point behind it).
  const double back =
      std::min(std::max(0.0, along_m), unlit + p_.relight_overlap_m + (lamps_were_on ? p_.relight_run_up_m : 0.0));
  if (!lamps_were_on && (lit_.litUpTo() >= lit_.end() - 1e-3 || unlit <= 0.02)) return true;
  std::ostringstream o;
  o << "back " << back << " m over the stretch passed with the lights off";
  log(o.str());
  MotionLimits slow = p_.motion;
  slow.max_speed_mps = std::min(slow.max_speed_mps, p_.rail_run.slow_speed_mps);
  const Loop l = runStep({MotionStep::Kind::kTranslate, -back, "back to the last lit point"}, ctx, slow);
  if (l == Loop::kPreempted) *preempted = true;
  if (l == Loop::kDone) return true;
  skip_reason_ = "treatment stopped: reversing to the last lit point failed";
  return false;
}

}  // namespace greenhouse_rail_nav
