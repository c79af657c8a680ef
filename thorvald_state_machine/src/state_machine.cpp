#include "thorvald_state_machine/state_machine.h"

#include <algorithm>
#include <chrono>
#include <set>

namespace thorvald_state_machine {

std::string joinPath(const std::vector<std::string>& path) {
  std::string joined;
  for (const auto& part : path) {
    if (!joined.empty()) joined += '/';
    joined += part;
  }
  return joined;
}

/// Book-keeping of the outermost machine: preemption flag, active path, history, observer.
class StateMachine::RootContext : public ExecutionContext {
 public:
  RootContext(std::string machine, std::size_t capacity) : capacity_(std::max<std::size_t>(capacity, 1)) {
    status_.machine = std::move(machine);
    clock_ = [] { return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count(); };
  }

  bool preemptRequested() const override { return preempt_.load(); }

  void enterState(const std::vector<std::string>& path) override {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      active_ = path;
      status_.active_state = joinPath(active_);
    }
    notify();
  }

  void finishState(const std::vector<std::string>& path, const std::string& outcome, const std::string& next) override {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      history_.push_back(TransitionRecord{clock_(), joinPath(path), outcome, next});
      while (history_.size() > capacity_) history_.pop_front();
      status_.last_outcome = outcome;
      ++status_.transitions;
    }
    notify();
  }

  void leaveDepth(std::size_t depth) override {
    std::lock_guard<std::mutex> lock(mutex_);
    if (active_.size() > depth) active_.resize(depth);
    status_.active_state = joinPath(active_);
  }

  void start() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      preempt_ = false;
      history_.clear();
      active_.clear();
      status_.active_state.clear();
      status_.last_outcome.clear();
      status_.transitions = 0;
      status_.running = true;
    }
    notify();
  }

  void stop(const std::string& outcome) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      active_.clear();
      status_.active_state.clear();
      if (!outcome.empty()) status_.last_outcome = outcome;
      status_.running = false;
      preempt_ = false;
    }
    notify();
  }

  void requestPreempt() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (status_.running) preempt_ = true;
  }

  StatusSnapshot snapshot() const {
    std::lock_guard<std::mutex> lock(mutex_);
    StatusSnapshot copy = status_;
    copy.preempt_requested = preempt_.load();
    copy.history.assign(history_.begin(), history_.end());
    return copy;
  }

  void setObserver(Observer observer) {
    std::lock_guard<std::mutex> lock(mutex_);
    observer_ = std::move(observer);
  }

  void setClock(Clock clock) {
    std::lock_guard<std::mutex> lock(mutex_);
    clock_ = std::move(clock);
  }

 private:
  void notify() {
    Observer observer;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      observer = observer_;
    }
    if (observer) observer(snapshot());
  }

  mutable std::mutex mutex_;
  std::atomic<bool> preempt_{false};
  std::size_t capacity_;
  StatusSnapshot status_;
  std::vector<std::string> active_;
  std::deque<TransitionRecord> history_;
  Observer observer_;
  Clock clock_;
};

/// Context handed to the states of a machine: prefixes their paths with the machine's active state
/// and forwards everything else to the context the machine itself runs in.
class StateMachine::NestedContext : public ExecutionContext {
 public:
  NestedContext(ExecutionContext& parent, std::string state) : parent_(parent), state_(std::move(state)) {}
  bool preemptRequested() const override { return parent_.preemptRequested(); }
  void enterState(const std::vector<std::string>& path) override { parent_.enterState(prefixed(path)); }
  void finishState(const std::vector<std::string>& path, const std::string& outcome, const std::string& next) override {
    parent_.finishState(prefixed(path), outcome, next);
  }
  void leaveDepth(std::size_t depth) override { parent_.leaveDepth(depth + 1); }

 private:
  std::vector<std::string> prefixed(const std::vector<std::string>& path) const {
    std::vector<std::string> full{state_};
    full.insert(full.end(), path.begin(), path.end());
    return full;
  }
  ExecutionContext& parent_;
  std::string state_;
};

StateMachine::StateMachine(std::string name, std::vector<std::string> outcomes, std::size_t history_capacity)
    : name_(std::move(name)), outcomes_(std::move(outcomes)) {
  if (std::find(outcomes_.begin(), outcomes_.end(), kPreempted) == outcomes_.end()) outcomes_.push_back(kPreempted);
  root_ = std::make_unique<RootContext>(name_, history_capacity);
}

StateMachine::~StateMachine() = default;

void StateMachine::add(const std::string& name, std::unique_ptr<State> state, Transitions transitions) {
  if (name.empty()) throw ExecutionError("machine '" + name_ + "': a state needs a name");
  if (!state) throw ExecutionError("machine '" + name_ + "': state '" + name + "' is null");
  if (states_.count(name)) throw ExecutionError("machine '" + name_ + "': state '" + name + "' added twice");
  states_[name] = Entry{std::move(state), std::move(transitions)};
  order_.push_back(name);
  if (initial_.empty()) initial_ = name;
}

void StateMachine::setInitialState(const std::string& name) { initial_ = name; }

bool StateMachine::isOutcome(const std::string& name) const {
  return std::find(outcomes_.begin(), outcomes_.end(), name) != outcomes_.end();
}

std::vector<std::string> StateMachine::validate() const {
  std::vector<std::string> problems;
  const std::string who = "machine '" + name_ + "': ";
  if (states_.empty()) {
    problems.push_back(who + "has no states");
    return problems;
  }
  if (!states_.count(initial_)) problems.push_back(who + "initial state '" + initial_ + "' does not exist");
  for (const auto& name : order_) {
    const Entry& entry = states_.at(name);
    const auto declared = entry.state->outcomes();
    for (const auto& outcome : declared) {
      auto it = entry.transitions.find(outcome);
      if (it == entry.transitions.end()) {
        if (outcome != kPreempted) {
          problems.push_back(who + "outcome '" + outcome + "' of state '" + name + "' has no transition");
        }
        continue;
      }
      if (!states_.count(it->second) && !isOutcome(it->second)) {
        problems.push_back(who + "state '" + name + "' goes on '" + outcome + "' to '" + it->second +
                           "', which is neither a state nor an outcome of the machine");
      }
    }
    for (const auto& transition : entry.transitions) {
      if (std::find(declared.begin(), declared.end(), transition.first) == declared.end()) {
        problems.push_back(who + "state '" + name + "' has a transition for '" + transition.first +
                           "', which is not one of its outcomes");
      }
    }
  }
  // Reachability from the initial state.
  if (states_.count(initial_)) {
    std::set<std::string> seen{initial_};
    std::vector<std::string> frontier{initial_};
    while (!frontier.empty()) {
      const std::string current = frontier.back();
      frontier.pop_back();
      for (const auto& transition : states_.at(current).transitions) {
        if (states_.count(transition.second) && seen.insert(transition.second).second) {
          frontier.push_back(transition.second);
        }
      }
    }
    for (const auto& name : order_) {
      if (!seen.count(name)) problems.push_back(who + "state '" + name + "' cannot be reached");
    }
  }
  return problems;
}

std::string StateMachine::run(UserData& userdata) {
  const auto problems = validate();
  if (!problems.empty()) {
    std::string message = problems.front();
    for (std::size_t i = 1; i < problems.size(); ++i) message += "; " + problems[i];
    throw ExecutionError(message);
  }
  root_->start();
  std::string outcome;
  try {
    outcome = runStates(userdata, *root_);
  } catch (...) {
    root_->stop("");
    throw;
  }
  root_->stop(outcome);
  return outcome;
}

std::string StateMachine::execute(UserData& userdata, ExecutionContext& context) {
  const auto problems = validate();
  if (!problems.empty()) throw ExecutionError(problems.front());
  return runStates(userdata, context);
}

std::string StateMachine::runStates(UserData& userdata, ExecutionContext& context) {
  std::string current = initial_;
  while (true) {
    if (context.preemptRequested()) {
      context.leaveDepth(0);
      return kPreempted;
    }
    Entry& entry = states_.at(current);
    context.enterState({current});
    NestedContext nested(context, current);
    const std::string outcome = entry.state->execute(userdata, nested);
    const auto declared = entry.state->outcomes();
    if (std::find(declared.begin(), declared.end(), outcome) == declared.end()) {
      throw ExecutionError("machine '" + name_ + "': state '" + current + "' returned undeclared outcome '" + outcome +
                           "'");
    }
    auto it = entry.transitions.find(outcome);
    const std::string next = it != entry.transitions.end() ? it->second : kPreempted;
    if (!states_.count(next)) {
      context.finishState({current}, outcome, "-> " + next);
      context.leaveDepth(0);
      return next;
    }
    context.finishState({current}, outcome, next);
    current = next;
  }
}

void StateMachine::requestPreempt() { root_->requestPreempt(); }
StatusSnapshot StateMachine::status() const { return root_->snapshot(); }
void StateMachine::setObserver(Observer observer) { root_->setObserver(std::move(observer)); }
void StateMachine::setClock(Clock clock) { root_->setClock(std::move(clock)); }
std::vector<std::string> StateMachine::stateNames() const { return order_; }

}  // namespace thorvald_state_machine
