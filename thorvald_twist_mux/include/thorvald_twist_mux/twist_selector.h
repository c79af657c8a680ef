#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "thorvald_twist_mux/mux_config.h"

namespace thorvald_twist_mux {

/// Decides which velocity input reaches the base. Holds per input the time of its last message and per lock its
/// last Bool and when it was heard; all times are seconds on one clock chosen by the caller (ROS time in the node).
///
/// Rules (twist_mux's): an input competes while it has been heard and, with a timeout > 0, its last message is no
/// older than the timeout; it is masked while a lock of strictly higher priority is engaged; among the competing
/// inputs the highest priority wins, ties go to the first listed. A lock is engaged while its last Bool was true
/// or, with a timeout > 0, while it has not been heard within the timeout (a watchdog, engaged until first heard).
/// Differences from twist_mux: an input never heard does not compete even with timeout 0, and priority 0 can win.
class TwistSelector {
 public:
  static constexpr int kNone = -1;

  /// `config` must have passed validateMuxConfig.
  explicit TwistSelector(MuxConfig config);

  /// Records a message on input `index` received at `now_s` [s]. Returns true when that input is the winner, i.e.
  /// its message is to be published; it then becomes the driving input.
  bool acceptInput(std::size_t index, double now_s);
  /// Records a Bool `engaged` on lock `index` received at `now_s` [s].
  void acceptLock(std::size_t index, bool engaged, double now_s);

  /// Returns true exactly once when the driving input (the one whose message was published last) has timed out or
  /// has been masked by a lock since; the caller then publishes one zero twist. A takeover by a higher-priority
  /// input is not a loss: its own message was published.
  bool takeDrivingLoss(double now_s);

  /// Index of the winning input at `now_s`, or kNone.
  int activeInput(double now_s) const;
  /// Priority of the highest engaged lock at `now_s`, or kNone when no lock is engaged.
  int lockPriority(double now_s) const;

  bool inputHeard(std::size_t index) const { return inputs_[index].heard; }
  bool inputExpired(std::size_t index, double now_s) const;
  bool inputMasked(std::size_t index, double now_s) const;
  /// Age of the input's last message [s]; negative when never heard.
  double inputAge(std::size_t index, double now_s) const;
  bool lockEngaged(std::size_t index, double now_s) const;
  /// True when the lock is engaged because its watchdog expired (or it was never heard), not by a true Bool.
  bool lockByWatchdog(std::size_t index, double now_s) const;
  /// Age of the lock's last message [s]; negative when never heard.
  double lockAge(std::size_t index, double now_s) const;

  const MuxConfig& config() const { return config_; }
  /// Index of the input whose message was published last and not yet lost, or kNone.
  int drivingInput() const { return driving_; }

 private:
  struct InputState {
    bool heard = false;
    double stamp_s = 0.0;
  };
  struct LockState {
    bool heard = false;
    bool value = false;
    double stamp_s = 0.0;
  };

  MuxConfig config_;
  std::vector<InputState> inputs_;
  std::vector<LockState> locks_;
  int driving_ = kNone;
};

/// Comma-separated names of the engaged locks at `now_s` in listed order; empty when none.
std::string engagedLockNames(const TwistSelector& selector, double now_s);

}  // namespace thorvald_twist_mux
