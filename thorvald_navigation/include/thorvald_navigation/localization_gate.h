#pragma once

#include <string>

namespace thorvald_navigation {

/// The localiser's status as it reports it (map_localizer's `~status`: "localized", "uncertain", "lost",
/// "no pose"); kUnknown until a status arrives (amcl publishes none).
enum class LocalizerState { kUnknown, kLocalized, kUncertain, kLost, kNoPose };

/// Parses a status text; false (and `state` untouched) when the text is none of the four.
bool parseLocalizerState(const std::string& text, LocalizerState* state);
const char* localizerStateName(LocalizerState s);

/// Settings of the gate; validate() names the bad one.
struct LocalizationGateParams {
  double lost_wait_s = 30.0;       ///< a goal is aborted when the robot has waited this long for relocalisation [s]
  double uncertain_wait_s = 15.0;  ///< at the goal, the pose is judged only once certain; abort after this [s]
  std::string validate() const;
};

enum class GateAction { kDrive, kHold, kAbort };

struct GateVerdict {
  GateAction action = GateAction::kDrive;
  std::string reason;  ///< why the robot holds or the goal is aborted
};

/// Decides whether the navigator may drive on the localised pose. A lost localiser (or one without a pose) holds
/// the robot where it stands until it reports localized or uncertain again, and aborts the goal after
/// lost_wait_s; an uncertain one lets the robot drive (its matches are used, the pose is roughly right) but a goal
/// is judged reached only on a localized pose. Without any status (kUnknown) the gate always lets it
/// drive, so a localiser that reports none (amcl) works as before. Times are seconds on any monotonic clock.
class LocalizationGate {
 public:
  explicit LocalizationGate(const LocalizationGateParams& params = {}) : params_(params) {}

  /// A new status at time `now_s` [s]; the time of the last change is kept.
  void setStatus(LocalizerState state, double now_s);
  LocalizerState state() const { return state_; }

  /// While driving a goal that started at `goal_start_s` [s]: the waiting time counts from whichever is later.
  GateVerdict whileDriving(double now_s, double goal_start_s) const;
  /// Standing at the goal since `arrived_s` [s]: may its pose be judged against the tolerances? Uncertainty is
  /// waited for from the arrival on, loss from the goal's start.
  GateVerdict atGoal(double now_s, double goal_start_s, double arrived_s) const;

 private:
  double waited(double now_s, double goal_start_s) const;

  LocalizationGateParams params_;
  LocalizerState state_ = LocalizerState::kUnknown;
  double since_s_ = 0.0;
};

}  // namespace thorvald_navigation
