#pragma once

#include <atomic>
#include <cstddef>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <vector>

#include "thorvald_state_machine/status_snapshot.h"
#include "thorvald_state_machine/state.h"

namespace thorvald_state_machine {

/// Thrown when a machine is run with an unsound structure, or a state returns an undeclared outcome.
class ExecutionError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

/// A finite state machine of named states and outcome-labelled transitions (the SMACH model).
///
/// Each state runs to completion and returns an outcome; the transition table sends the machine to
/// the next state or ends it with one of the machine's own outcomes. A machine is itself a State, so
/// machines nest. Preemption is cooperative: requestPreempt() sets a flag that the machine checks
/// before every state and that blocking states poll; the machine then returns kPreempted, which is
/// always one of its outcomes. An outcome kPreempted of a state without an explicit transition ends
/// the machine with kPreempted.
///
/// Threads: run() executes in the caller's thread; requestPreempt(), status() and the observer are
/// safe to use from other threads (the observer is called in the running thread, without locks held).
class StateMachine : public State {
 public:
  using Transitions = std::map<std::string, std::string>;  ///< state outcome -> state name or machine outcome
  using Observer = std::function<void(const StatusSnapshot&)>;
  using Clock = std::function<double()>;  ///< returns the time [s] stamped on history records

  /// `outcomes`: the machine's own outcomes (kPreempted is added when absent).
  /// `history_capacity`: number of transitions kept for status() (>= 1).
  StateMachine(std::string name, std::vector<std::string> outcomes, std::size_t history_capacity = 32);
  ~StateMachine() override;

  /// Adds a state. The first state added is the initial one unless setInitialState() says otherwise.
  /// Throws ExecutionError on an empty or duplicate name or a null state.
  void add(const std::string& name, std::unique_ptr<State> state, Transitions transitions);
  void setInitialState(const std::string& name);

  /// Problems with the structure (unknown targets, unmapped outcomes, no states, unknown initial
  /// state, states that cannot be reached), one sentence each; empty when the machine is sound.
  std::vector<std::string> validate() const;

  /// Runs the machine as the outermost one from its initial state and returns its outcome.
  /// Clears the history and any preemption served earlier. Throws ExecutionError when validate()
  /// finds a problem or a state returns an undeclared outcome; exceptions of states propagate.
  std::string run(UserData& userdata);

  /// Asks the running machine (and its nested machines) to stop; no effect when idle.
  void requestPreempt();

  /// A consistent snapshot of the machine (thread-safe).
  StatusSnapshot status() const;

  /// Called after every transition and when the machine starts and stops.
  void setObserver(Observer observer);
  /// Clock for history stamps; defaults to seconds of std::chrono::system_clock.
  void setClock(Clock clock);

  const std::string& name() const { return name_; }
  std::vector<std::string> stateNames() const;

  // State interface: used when this machine is nested in another one.
  std::vector<std::string> outcomes() const override { return outcomes_; }
  std::string execute(UserData& userdata, ExecutionContext& context) override;

 private:
  struct Entry {
    std::unique_ptr<State> state;
    Transitions transitions;
  };
  class RootContext;
  class NestedContext;

  std::string runStates(UserData& userdata, ExecutionContext& context);
  bool isOutcome(const std::string& name) const;

  std::string name_;
  std::vector<std::string> outcomes_;
  std::map<std::string, Entry> states_;
  std::vector<std::string> order_;  ///< insertion order, for stable reports
  std::string initial_;
  std::unique_ptr<RootContext> root_;
};

}  // namespace thorvald_state_machine
