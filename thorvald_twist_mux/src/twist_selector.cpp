#include "thorvald_twist_mux/twist_selector.h"

#include <utility>

namespace thorvald_twist_mux {

TwistSelector::TwistSelector(MuxConfig config)
    : config_(std::move(config)), inputs_(config_.inputs.size()), locks_(config_.locks.size()) {}

bool TwistSelector::acceptInput(std::size_t index, double now_s) {
  inputs_[index].heard = true;
  inputs_[index].stamp_s = now_s;
  const bool wins = activeInput(now_s) == static_cast<int>(index);
  if (wins) driving_ = static_cast<int>(index);
  return wins;
}

void TwistSelector::acceptLock(std::size_t index, bool engaged, double now_s) {
  locks_[index].heard = true;
  locks_[index].value = engaged;
  locks_[index].stamp_s = now_s;
}

bool TwistSelector::takeDrivingLoss(double now_s) {
  if (driving_ == kNone) return false;
  const auto index = static_cast<std::size_t>(driving_);
  if (!inputExpired(index, now_s) && !inputMasked(index, now_s)) return false;
  driving_ = kNone;
  return true;
}

int TwistSelector::activeInput(double now_s) const {
  const int lock_priority = lockPriority(now_s);
  int best = kNone;
  for (std::size_t i = 0; i < inputs_.size(); ++i) {
    if (!inputs_[i].heard || inputExpired(i, now_s) || config_.inputs[i].priority < lock_priority) continue;
    if (best == kNone || config_.inputs[i].priority > config_.inputs[static_cast<std::size_t>(best)].priority) {
      best = static_cast<int>(i);
    }
  }
  return best;
}

int TwistSelector::lockPriority(double now_s) const {
  int priority = kNone;
  for (std::size_t i = 0; i < locks_.size(); ++i) {
    if (lockEngaged(i, now_s) && config_.locks[i].priority > priority) priority = config_.locks[i].priority;
  }
  return priority;
}

bool TwistSelector::inputExpired(std::size_t index, double now_s) const {
  const double timeout = config_.inputs[index].timeout_s;
  return timeout > 0.0 && inputs_[index].heard && now_s - inputs_[index].stamp_s > timeout;
}

bool TwistSelector::inputMasked(std::size_t index, double now_s) const {
  return config_.inputs[index].priority < lockPriority(now_s);
}

double TwistSelector::inputAge(std::size_t index, double now_s) const {
  return inputs_[index].heard ? now_s - inputs_[index].stamp_s : -1.0;
}

bool TwistSelector::lockEngaged(std::size_t index, double now_s) const {
  return locks_[index].value || lockByWatchdog(index, now_s);
}

bool TwistSelector::lockByWatchdog(std::size_t index, double now_s) const {
  const double timeout = config_.locks[index].timeout_s;
  if (timeout <= 0.0) return false;
  return !locks_[index].heard || now_s - locks_[index].stamp_s > timeout;
}

double TwistSelector::lockAge(std::size_t index, double now_s) const {
  return locks_[index].heard ? now_s - locks_[index].stamp_s : -1.0;
}

std::string engagedLockNames(const TwistSelector& selector, double now_s) {
  std::string names;
  for (std::size_t i = 0; i < selector.config().locks.size(); ++i) {
    if (!selector.lockEngaged(i, now_s)) continue;
    if (!names.empty()) names += ",";
    names += selector.config().locks[i].name;
  }
  return names;
}

}  // namespace thorvald_twist_mux
