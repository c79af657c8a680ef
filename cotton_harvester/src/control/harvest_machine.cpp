#include "cotton_harvester/control/harvest_machine.h"

#include <algorithm>
#include <cmath>

namespace cotton_harvester {
namespace control {

namespace tsm = thorvald_state_machine;

std::string HarvestParams::check() const {
  if (auto bad = decision.check(); !bad.empty()) return bad;
  if (!(tracker.match_radius_m > 0.0)) return "match_radius_m: expected > 0";
  if (!(tracker.max_pick_attempts >= 1)) return "max_pick_attempts: expected >= 1";
  if (!(tracker.max_align_moves >= 1)) return "max_align_moves: expected >= 1";
  if (!(tracker.along_row_band_m >= 0.0)) return "along_row_band_m: expected >= 0";
  if (!(max_rover_step_m > 0.0)) return "max_rover_step_m: expected > 0";
  if (!(pass_step_m > 0.0)) return "pass_step_m: expected > 0";
  if (!(row_length_m > 0.0)) return "row_length_m: expected > 0";
  if (!(max_missed_observations >= 1)) return "max_missed_observations: expected >= 1";
  if (!(max_failed_actions >= 1)) return "max_failed_actions: expected >= 1";
  if (!(bolls_present >= 0)) return "bolls_present: expected >= 0";
  if (!(remember_target_frames >= 0)) return "remember_target_frames: expected >= 0";
  if (!(revisit_window_m >= 0.0)) return "revisit_window_m: expected >= 0";
  if (!(search_spacing_m > 0.0) || !std::isfinite(search_spacing_m)) return "search_spacing_m: expected > 0";
  if (auto bad = actions.check(); !bad.empty()) return bad;
  if (search_under_leaves && !(actions.arm.rest_depth_m > 0.0))
    return "rest_depth_m: expected > 0 with search_under_leaves (the search looks from above the plants)";
  return "";
}

HarvestMachine::HarvestMachine(HarvestPlant& plant, const HarvestParams& params)
    : plant_(plant), params_(params), actions_(plant, params.actions), tracker_(params.tracker) {
  params_.tracker.y_forward_sign = params_.decision.y_forward_sign;
  tracker_ = BollTracker(params_.tracker);
  machine_ = std::make_unique<tsm::StateMachine>("harvest", std::vector<std::string>{"finished", "aborted"}, 64);
  const std::vector<std::string> action_outcomes{"done", "failed", "give_up", tsm::kPreempted};
  const tsm::StateMachine::Transitions back{{"done", "OBSERVE"}, {"failed", "OBSERVE"}, {"give_up", "aborted"}};
  machine_->add("OBSERVE",
                std::make_unique<tsm::FunctionState>(
                    std::vector<std::string>{"forward", "backward", "arm_up", "arm_down", "pick", "pass_on", "search",
                                             "retry", "lost", tsm::kPreempted},
                    [this](tsm::UserData& ud, tsm::ExecutionContext& ctx) { return observe(ud, ctx); }),
                {{"forward", "MOVE_FORWARD"},
                 {"backward", "MOVE_BACKWARD"},
                 {"arm_up", "ARM_UP"},
                 {"arm_down", "ARM_DOWN"},
                 {"pick", "PICK"},
                 {"pass_on", "PASS_ON"},
                 {"search", "SEARCH_LEAVES"},
                 {"retry", "OBSERVE"},
                 {"lost", "aborted"}});
  const std::pair<const char*, HarvestAction> actions[] = {{"MOVE_FORWARD", HarvestAction::kForward},
                                                           {"MOVE_BACKWARD", HarvestAction::kBackward},
                                                           {"ARM_UP", HarvestAction::kArmUp},
                                                           {"ARM_DOWN", HarvestAction::kArmDown},
                                                           {"PICK", HarvestAction::kPick}};
  for (const auto& [name, action] : actions) {
    const HarvestAction a = action;
    machine_->add(
        name,
        std::make_unique<tsm::FunctionState>(
            action_outcomes, [this, a](tsm::UserData& ud, tsm::ExecutionContext& ctx) { return act(a, ud, ctx); }),
        back);
  }
  machine_->add("PASS_ON",
                std::make_unique<tsm::FunctionState>(
                    std::vector<std::string>{"done", "failed", "give_up", "row_end", tsm::kPreempted},
                    [this](tsm::UserData&, tsm::ExecutionContext& ctx) { return passOn(ctx); }),
                {{"done", "OBSERVE"}, {"failed", "OBSERVE"}, {"give_up", "aborted"}, {"row_end", "finished"}});
  machine_->add("SEARCH_LEAVES",
                std::make_unique<tsm::FunctionState>(
                    std::vector<std::string>{"done", "nothing", "failed", "give_up", tsm::kPreempted},
                    [this](tsm::UserData&, tsm::ExecutionContext& ctx) { return searchLeaves(ctx); }),
                {{"done", "OBSERVE"}, {"nothing", "PASS_ON"}, {"failed", "OBSERVE"}, {"give_up", "aborted"}});
}

std::string HarvestMachine::run() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    tracker_ = BollTracker(params_.tracker);
    start_time_s_ = last_time_s_ = plant_.now();
    start_position_m_ = last_position_m_ = plant_.roverPositionM();
    missed_ = failed_actions_ = rejected_frames_ = 0;
    target_id_ = 0;
    decision_points_.reset();
    searched_m_.clear();
    abort_reason_.clear();
  }
  tsm::UserData userdata;
  return machine_->run(userdata);
}

HarvestCounts HarvestMachine::counts() const {
  std::lock_guard<std::mutex> lock(mutex_);
  HarvestCounts counts;
  counts.bolls_present = params_.bolls_present;
  counts.detected = tracker_.detected();
  counts.reached = tracker_.reached();
  counts.picked = tracker_.picked();
  counts.skipped = tracker_.skipped();
  counts.pick_attempts = tracker_.pickAttempts();
  counts.time_s = last_time_s_ - start_time_s_;
  counts.distance_m = std::abs(last_position_m_ - start_position_m_);
  return counts;
}

std::vector<TrackedBoll> HarvestMachine::tracks() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return tracker_.tracks();
}

std::optional<std::pair<Point3, Point3>> HarvestMachine::lastDecisionPoints() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return decision_points_;
}

int HarvestMachine::rejectedFrames() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return rejected_frames_;
}

std::string HarvestMachine::abortReason() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return abort_reason_;
}

std::string HarvestMachine::missedObservation(const std::string& why) {
  if (++missed_ < params_.max_missed_observations) return "retry";
  abort_reason_ = std::to_string(missed_) + " frames in a row unusable, the last: " + why;
  return "lost";
}

std::string HarvestMachine::observe(tsm::UserData& ud, tsm::ExecutionContext& ctx) {
  const auto preempted = [&ctx] { return ctx.preemptRequested(); };
  const auto observation = plant_.observe(preempted);
  std::lock_guard<std::mutex> lock(mutex_);
  last_time_s_ = plant_.now();
  last_position_m_ = plant_.roverPositionM();
  if (ctx.preemptRequested()) return tsm::kPreempted;
  if (!observation) {
    const std::string failure = plant_.lastFailure();
    return missedObservation(failure.empty() ? "no frame" : failure);
  }

  const std::vector<int> ids = tracker_.update(*observation);
  while (true) {
    const auto index = tracker_.nearestPending(*observation, ids);
    std::optional<Point3> boll;
    int id = 0;
    if (params_.keep_target && (boll = keptTarget(*observation, ids))) {
      id = target_id_;
    } else if (index) {
      boll = observation->bolls[*index].position;
      id = ids[*index];
    } else if ((boll = rememberedTarget(*observation))) {
      id = target_id_;
    } else if (params_.revisit_pending) {
      boll = revisitTarget(*observation, ids, &id);
    }
    if (!boll) {
      missed_ = 0;
      return searchDue() ? "search" : "pass_on";
    }
    const auto& ee = observation->end_effector;
    if (!ee || !std::isfinite(ee->x) || !std::isfinite(ee->y) || !std::isfinite(ee->z)) {
      ++rejected_frames_;
      return missedObservation("no end effector in the frame");
    }
    missed_ = 0;
    HarvestDecision decision = decide(*boll, *ee, params_.decision);
    if (decision.action == HarvestAction::kOutOfReach) {
      tracker_.skip(id);
      continue;
    }
    // Before the rover leaves a place not searched yet, and by at most the search spacing, so no strip of the row
    // goes unsearched.
    if (decision.action == HarvestAction::kForward && params_.search_under_leaves) {
      if (searchDue()) return "search";
      decision.rover_move_m = std::min(decision.rover_move_m, params_.search_spacing_m);
    }
    if (decision.action != HarvestAction::kPick) {
      tracker_.noteAlignMove(id);
      if (tracker_.find(id)->fate == BollFate::kSkipped) continue;
    }
    decision.rover_move_m = std::clamp(decision.rover_move_m, -params_.max_rover_step_m, params_.max_rover_step_m);
    decision_ = decision;
    target_id_ = id;
    decision_points_ = std::make_pair(*boll, *ee);
    ud.set<int>("target_boll", id);
    ud.set<std::string>("action", toString(decision.action));
    return toString(decision.action);
  }
}

std::optional<Point3> HarvestMachine::revisitTarget(const HarvestObservation& observation, const std::vector<int>& ids,
                                                    int* id) const {
  const TrackedBoll* best = nullptr;
  const double sign = params_.decision.y_forward_sign;
  for (const auto& t : tracker_.tracks()) {
    if (t.fate != BollFate::kPending || !t.seen_reachable || t.sightings < 2) continue;
    if (std::find(ids.begin(), ids.end(), t.id) != ids.end()) continue;  // in this frame, and not reachable
    const double along = (t.along_row_m - observation.rover_position_m) * sign;
    if (std::abs(along) > params_.revisit_window_m) continue;
    if (!best || along < (best->along_row_m - observation.rover_position_m) * sign) best = &t;
  }
  if (!best) return std::nullopt;
  *id = best->id;
  return Point3{best->across_m, (best->along_row_m - observation.rover_position_m) * sign, best->depth_m};
}

std::optional<Point3> HarvestMachine::keptTarget(const HarvestObservation& observation,
                                                 const std::vector<int>& ids) const {
  const TrackedBoll* track = target_id_ == 0 ? nullptr : tracker_.find(target_id_);
  if (!track || track->fate != BollFate::kPending) return std::nullopt;
  for (std::size_t i = 0; i < ids.size() && i < observation.bolls.size(); ++i)
    if (ids[i] == target_id_ && observation.bolls[i].reachable) return observation.bolls[i].position;
  return rememberedTarget(observation);
}

std::optional<Point3> HarvestMachine::rememberedTarget(const HarvestObservation& observation) const {
  if (params_.remember_target_frames <= 0 || target_id_ == 0) return std::nullopt;
  const TrackedBoll* track = tracker_.find(target_id_);
  if (!track || track->fate != BollFate::kPending) return std::nullopt;
  if (tracker_.frame() - track->last_seen_frame > params_.remember_target_frames) return std::nullopt;
  // along_row = rover position + y_forward_sign * camera y (BollTracker).
  const double y = (track->along_row_m - observation.rover_position_m) * params_.decision.y_forward_sign;
  return Point3{track->across_m, y, track->depth_m};
}

std::string HarvestMachine::resultOutcome(MoveResult result) {
  std::lock_guard<std::mutex> lock(mutex_);
  last_time_s_ = plant_.now();
  last_position_m_ = plant_.roverPositionM();
  switch (result) {
    case MoveResult::kDone:
      failed_actions_ = 0;
      return "done";
    case MoveResult::kPreempted:
      return tsm::kPreempted;
    case MoveResult::kFailed:
    default: {
      if (++failed_actions_ < params_.max_failed_actions) return "failed";
      const std::string failure = plant_.lastFailure();
      abort_reason_ = std::to_string(failed_actions_) + " rover/arm actions failed in a row" +
                      (failure.empty() ? "" : ", the last: " + failure);
      return "give_up";
    }
  }
}

std::string HarvestMachine::act(HarvestAction action, tsm::UserData&, tsm::ExecutionContext& ctx) {
  const auto preempted = [&ctx] { return ctx.preemptRequested(); };
  HarvestDecision decision;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    decision = decision_;
    if (action == HarvestAction::kPick) tracker_.notePick(target_id_);  // judged on the next frame
  }
  switch (action) {
    case HarvestAction::kForward:
    case HarvestAction::kBackward:
      return resultOutcome(actions_.moveRover(decision.rover_move_m, preempted));
    case HarvestAction::kArmUp:
    case HarvestAction::kArmDown:
      return resultOutcome(actions_.armToDepth(decision.arm_depth_m, preempted));
    case HarvestAction::kPick:
      return resultOutcome(actions_.pick(decision.pick_offset_m, preempted));
    default:
      return "failed";
  }
}

std::string HarvestMachine::passOn(tsm::ExecutionContext& ctx) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (std::abs(plant_.roverPositionM() - start_position_m_) >= params_.row_length_m) {
      last_time_s_ = plant_.now();
      last_position_m_ = plant_.roverPositionM();
      return "row_end";
    }
  }
  const double step =
      params_.search_under_leaves ? std::min(params_.pass_step_m, params_.search_spacing_m) : params_.pass_step_m;
  return resultOutcome(actions_.moveRover(step, [&ctx] { return ctx.preemptRequested(); }));
}

bool HarvestMachine::searchDue() const {
  if (!params_.search_under_leaves) return false;
  const double here = plant_.roverPositionM();
  for (const double s : searched_m_)
    if (std::abs(here - s) < 0.5 * params_.search_spacing_m) return false;
  return true;
}

std::string HarvestMachine::searchLeaves(tsm::ExecutionContext& ctx) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    searched_m_.push_back(plant_.roverPositionM());
  }
  const auto result = actions_.searchUnderLeaves([&ctx] { return ctx.preemptRequested(); });
  if (ctx.preemptRequested()) return tsm::kPreempted;
  if (!result) return "nothing";
  return resultOutcome(*result);
}

}  // namespace control
}  // namespace cotton_harvester
