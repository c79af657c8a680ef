#pragma once

#include <atomic>
#include <functional>
#include <string>
#include <vector>

#include "thorvald_state_machine/user_data.h"

namespace thorvald_state_machine {

/// The outcome every machine and every preemptible state uses when it stopped on request.
inline const std::string kPreempted = "preempted";

/// What a running state may ask of the machine that runs it: whether a preemption was requested,
/// and a way to report the transitions of nested machines to the outermost one (for introspection).
class ExecutionContext {
 public:
  virtual ~ExecutionContext() = default;
  /// True once someone asked the outermost machine to stop; states that block should poll it.
  virtual bool preemptRequested() const = 0;
  /// Called by a nested machine when one of its states becomes active (`path` relative to it).
  virtual void enterState(const std::vector<std::string>& path) = 0;
  /// Called by a nested machine when one of its states finished.
  virtual void finishState(const std::vector<std::string>& path, const std::string& outcome,
                           const std::string& next) = 0;
  /// Called when a nested machine leaves (its active path must shrink back to `depth` entries).
  virtual void leaveDepth(std::size_t depth) = 0;
};

/// One state of a machine: it runs to completion and returns one of its declared outcomes.
/// A state that blocks (waits for a sensor, a move) must poll `context.preemptRequested()` and
/// return kPreempted promptly; kPreempted must then be among its outcomes.
class State {
 public:
  virtual ~State() = default;
  /// Outcomes this state may return; the machine checks that each one has a transition.
  virtual std::vector<std::string> outcomes() const = 0;
  /// Runs the state. Must return one of outcomes(). May read and write `userdata`.
  virtual std::string execute(UserData& userdata, ExecutionContext& context) = 0;
};

/// A state made of a function, for small states and tests.
class FunctionState : public State {
 public:
  using Body = std::function<std::string(UserData&, ExecutionContext&)>;
  FunctionState(std::vector<std::string> outcomes, Body body)
      : outcomes_(std::move(outcomes)), body_(std::move(body)) {}
  std::vector<std::string> outcomes() const override { return outcomes_; }
  std::string execute(UserData& userdata, ExecutionContext& context) override { return body_(userdata, context); }

 private:
  std::vector<std::string> outcomes_;
  Body body_;
};

}  // namespace thorvald_state_machine
