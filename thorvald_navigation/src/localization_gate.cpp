#include "thorvald_navigation/localization_gate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace thorvald_navigation {

bool parseLocalizerState(const std::string& text, LocalizerState* state) {
  static const struct {
    const char* name;
    LocalizerState state;
  } kStates[] = {{"localized", LocalizerState::kLocalized},
                 {"uncertain", LocalizerState::kUncertain},
                 {"lost", LocalizerState::kLost},
                 {"no pose", LocalizerState::kNoPose}};
  for (const auto& s : kStates) {
    if (text == s.name) {
      *state = s.state;
      return true;
    }
  }
  return false;
}

const char* localizerStateName(LocalizerState s) {
  switch (s) {
    case LocalizerState::kUnknown:
      return "unknown";
    case LocalizerState::kLocalized:
      return "localized";
    case LocalizerState::kUncertain:
      return "uncertain";
    case LocalizerState::kLost:
      return "lost";
    case LocalizerState::kNoPose:
      return "no pose";
  }
  return "?";
}

std::string LocalizationGateParams::validate() const {
  if (!(lost_wait_s > 0.0) || !std::isfinite(lost_wait_s)) return "localization_lost_wait must be > 0 s";
  if (!(uncertain_wait_s > 0.0) || !std::isfinite(uncertain_wait_s)) return "localization_uncertain_wait must be > 0 s";
  return {};
}

void LocalizationGate::setStatus(LocalizerState state, double now_s) {
  if (state == state_) return;
  state_ = state;
  since_s_ = now_s;
}

double LocalizationGate::waited(double now_s, double goal_start_s) const {
  return std::max(0.0, now_s - std::max(since_s_, goal_start_s));
}

namespace {
std::string seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.1f s", s);
  return buf;
}
}  // namespace

GateVerdict LocalizationGate::whileDriving(double now_s, double goal_start_s) const {
  if (state_ != LocalizerState::kLost && state_ != LocalizerState::kNoPose) return {};
  const double w = waited(now_s, goal_start_s);
  const std::string what = std::string("localiser ") + localizerStateName(state_);
  if (w > params_.lost_wait_s)
    return {GateAction::kAbort,
            what + " for " + seconds(w) + ": no relocalisation, goal given up where the robot stands"};
  return {GateAction::kHold, what + ": stopped, waiting for relocalisation (" + seconds(w) + ")"};
}

GateVerdict LocalizationGate::atGoal(double now_s, double goal_start_s, double arrived_s) const {
  if (state_ != LocalizerState::kUncertain) return whileDriving(now_s, goal_start_s);
  const double w = waited(now_s, arrived_s);
  if (w > params_.uncertain_wait_s)
    return {GateAction::kAbort,
            "localiser uncertain for " + seconds(w) + " at the goal: the pose cannot be judged against the tolerances"};
  return {GateAction::kHold, "localiser uncertain: waiting for a certain pose before judging the goal"};
}

}  // namespace thorvald_navigation
