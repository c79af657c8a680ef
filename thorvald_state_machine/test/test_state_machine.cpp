#include <gtest/gtest.h>

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "thorvald_state_machine/state_machine.h"

namespace tsm = thorvald_state_machine;
using tsm::FunctionState;
using tsm::StateMachine;
using tsm::UserData;

namespace {

/// A state that returns the outcomes of a script in order and counts its runs.
std::unique_ptr<FunctionState> scripted(std::vector<std::string> outcomes, std::vector<std::string> script,
                                        int* runs = nullptr) {
  auto index = std::make_shared<std::size_t>(0);
  return std::make_unique<FunctionState>(outcomes, [script, index, runs](UserData&, tsm::ExecutionContext&) {
    if (runs) ++*runs;
    const std::string outcome = script.at(std::min(*index, script.size() - 1));
    ++*index;
    return outcome;
  });
}

}  // namespace

TEST(UserData, StoresTypedValuesAndNamesMissingKeys) {
  UserData data;
  data.set<int>("attempts", 2);
  data.set<std::string>("boll", "b1");
  EXPECT_EQ(data.get<int>("attempts"), 2);
  EXPECT_EQ(data.get<std::string>("boll"), "b1");
  EXPECT_EQ(data.getOr<double>("missing", 1.5), 1.5);
  EXPECT_TRUE(data.has("boll"));
  try {
    data.get<int>("nothing");
    FAIL() << "expected UserDataError";
  } catch (const tsm::UserDataError& e) {
    EXPECT_NE(std::string(e.what()).find("'nothing'"), std::string::npos);
  }
  EXPECT_THROW(data.get<double>("attempts"), tsm::UserDataError);
  EXPECT_THROW(data.set<double>("attempts", 1.0), tsm::UserDataError);
  data.erase("attempts");
  data.set<double>("attempts", 1.0);
  EXPECT_EQ(data.keys(), (std::vector<std::string>{"attempts", "boll"}));
}

TEST(StateMachine, FollowsTransitionsAndRecordsHistory) {
  StateMachine sm("demo", {"done"});
  sm.add("A", scripted({"next"}, {"next"}), {{"next", "B"}});
  sm.add("B", scripted({"again", "finish"}, {"again", "finish"}), {{"again", "A"}, {"finish", "done"}});
  double t = 10.0;
  sm.setClock([&t] { return t += 1.0; });
  UserData data;
  EXPECT_EQ(sm.run(data), "done");
  const auto status = sm.status();
  EXPECT_EQ(status.machine, "demo");
  EXPECT_FALSE(status.running);
  EXPECT_EQ(status.active_state, "");
  EXPECT_EQ(status.last_outcome, "done");
  EXPECT_EQ(status.transitions, 4u);
  ASSERT_EQ(status.history.size(), 4u);
  EXPECT_EQ(status.history[0].state, "A");
  EXPECT_EQ(status.history[0].next, "B");
  EXPECT_EQ(status.history[1].outcome, "again");
  EXPECT_EQ(status.history[3].state, "B");
  EXPECT_EQ(status.history[3].outcome, "finish");
  EXPECT_EQ(status.history[3].next, "-> done");
  EXPECT_DOUBLE_EQ(status.history[0].stamp_s, 11.0);
  EXPECT_DOUBLE_EQ(status.history[3].stamp_s, 14.0);
}

TEST(StateMachine, HistoryIsBoundedToCapacity) {
  StateMachine sm("loop", {"done"}, 3);
  int runs = 0;
  sm.add("A", scripted({"loop", "stop"}, {"loop", "loop", "loop", "loop", "stop"}, &runs),
         {{"loop", "A"}, {"stop", "done"}});
  UserData data;
  EXPECT_EQ(sm.run(data), "done");
  EXPECT_EQ(runs, 5);
  const auto status = sm.status();
  EXPECT_EQ(status.transitions, 5u);
  ASSERT_EQ(status.history.size(), 3u);
  EXPECT_EQ(status.history.back().outcome, "stop");
  EXPECT_EQ(status.history.front().outcome, "loop");
}

TEST(StateMachine, UserDataFlowsBetweenStates) {
  StateMachine sm("counter", {"done"});
  sm.add("COUNT",
         std::make_unique<FunctionState>(std::vector<std::string>{"more", "enough"},
                                         [](UserData& ud, tsm::ExecutionContext&) {
                                           const int n = ud.getOr<int>("n", 0) + 1;
                                           ud.set<int>("n", n);
                                           return n < 7 ? "more" : "enough";
                                         }),
         {{"more", "COUNT"}, {"enough", "done"}});
  UserData data;
  EXPECT_EQ(sm.run(data), "done");
  EXPECT_EQ(data.get<int>("n"), 7);
}

TEST(StateMachine, ValidateNamesEveryProblem) {
  StateMachine sm("broken", {"done"});
  EXPECT_EQ(sm.validate().size(), 1u);  // no states
  sm.add("A", scripted({"x", "y"}, {"x"}), {{"x", "NOWHERE"}, {"z", "done"}});
  sm.add("ORPHAN", scripted({"x"}, {"x"}), {{"x", "done"}});
  const auto problems = sm.validate();
  auto mentions = [&problems](const std::string& text) {
    for (const auto& p : problems)
      if (p.find(text) != std::string::npos) return true;
    return false;
  };
  EXPECT_TRUE(mentions("'NOWHERE'"));
  EXPECT_TRUE(mentions("outcome 'y' of state 'A' has no transition"));
  EXPECT_TRUE(mentions("transition for 'z'"));
  EXPECT_TRUE(mentions("'ORPHAN' cannot be reached"));
  UserData data;
  EXPECT_THROW(sm.run(data), tsm::ExecutionError);
  sm.setInitialState("MISSING");
  EXPECT_TRUE(mentions("NOWHERE"));
  bool initial_reported = false;
  for (const auto& p : sm.validate()) initial_reported |= p.find("initial state 'MISSING'") != std::string::npos;
  EXPECT_TRUE(initial_reported);
}

TEST(StateMachine, RejectsBadAdds) {
  StateMachine sm("m", {"done"});
  sm.add("A", scripted({"x"}, {"x"}), {{"x", "done"}});
  EXPECT_THROW(sm.add("A", scripted({"x"}, {"x"}), {}), tsm::ExecutionError);
  EXPECT_THROW(sm.add("", scripted({"x"}, {"x"}), {}), tsm::ExecutionError);
  EXPECT_THROW(sm.add("B", nullptr, {}), tsm::ExecutionError);
}

TEST(StateMachine, UndeclaredOutcomeThrowsAndStops) {
  StateMachine sm("m", {"done"});
  sm.add("A", scripted({"ok"}, {"surprise"}), {{"ok", "done"}});
  UserData data;
  try {
    sm.run(data);
    FAIL() << "expected ExecutionError";
  } catch (const tsm::ExecutionError& e) {
    EXPECT_NE(std::string(e.what()).find("'surprise'"), std::string::npos);
  }
  EXPECT_FALSE(sm.status().running);
}

TEST(StateMachine, StateExceptionsPropagateAndMachineStops) {
  StateMachine sm("m", {"done"});
  sm.add("A",
         std::make_unique<FunctionState>(
             std::vector<std::string>{"ok"},
             [](UserData&, tsm::ExecutionContext&) -> std::string { throw std::runtime_error("sensor gone"); }),
         {{"ok", "done"}});
  UserData data;
  EXPECT_THROW(sm.run(data), std::runtime_error);
  EXPECT_FALSE(sm.status().running);
}

TEST(StateMachine, PreemptedOutcomeIsAlwaysDeclared) {
  StateMachine sm("m", {"done"});
  const auto outcomes = sm.outcomes();
  EXPECT_NE(std::find(outcomes.begin(), outcomes.end(), tsm::kPreempted), outcomes.end());
}

TEST(StateMachine, NestedMachineReportsFullPaths) {
  auto inner = std::make_unique<StateMachine>("inner", std::vector<std::string>{"ok"});
  inner->add("X", scripted({"go"}, {"go"}), {{"go", "Y"}});
  inner->add("Y", scripted({"go"}, {"go"}), {{"go", "ok"}});
  StateMachine outer("outer", {"done"});
  std::vector<std::string> seen_active;
  outer.add("START", scripted({"go"}, {"go"}), {{"go", "SUB"}});
  outer.add("SUB", std::move(inner), {{"ok", "done"}});
  outer.setObserver([&seen_active](const tsm::StatusSnapshot& s) {
    if (seen_active.empty() || seen_active.back() != s.active_state) seen_active.push_back(s.active_state);
  });
  UserData data;
  EXPECT_EQ(outer.run(data), "done");
  const std::vector<std::string> expected{"", "START", "SUB", "SUB/X", "SUB/Y", "SUB", ""};
  EXPECT_EQ(seen_active, expected);
  const auto history = outer.status().history;
  ASSERT_EQ(history.size(), 4u);
  EXPECT_EQ(history[1].state, "SUB/X");
  EXPECT_EQ(history[2].state, "SUB/Y");
  EXPECT_EQ(history[2].next, "-> ok");
  EXPECT_EQ(history[3].state, "SUB");
  EXPECT_EQ(history[3].next, "-> done");
}

TEST(StateMachine, PreemptionStopsABlockingStateAndIsServedOnce) {
  // WAIT blocks until preempted; the test thread requests preemption once WAIT is active.
  std::mutex mutex;
  std::condition_variable cv;
  bool waiting = false;
  StateMachine sm("m", {"done"});
  sm.add("WAIT",
         std::make_unique<FunctionState>(std::vector<std::string>{"ok", tsm::kPreempted},
                                         [&](UserData&, tsm::ExecutionContext& ctx) {
                                           {
                                             std::lock_guard<std::mutex> lock(mutex);
                                             waiting = true;
                                           }
                                           cv.notify_all();
                                           while (!ctx.preemptRequested()) std::this_thread::yield();
                                           return tsm::kPreempted;
                                         }),
         {{"ok", "done"}});
  UserData data;
  std::string outcome;
  std::thread runner([&] { outcome = sm.run(data); });
  {
    std::unique_lock<std::mutex> lock(mutex);
    ASSERT_TRUE(cv.wait_for(lock, std::chrono::seconds(10), [&] { return waiting; }));
  }
  EXPECT_TRUE(sm.status().running);
  EXPECT_EQ(sm.status().active_state, "WAIT");
  sm.requestPreempt();
  runner.join();
  EXPECT_EQ(outcome, tsm::kPreempted);
  const auto status = sm.status();
  EXPECT_FALSE(status.running);
  EXPECT_FALSE(status.preempt_requested);
  EXPECT_EQ(status.last_outcome, tsm::kPreempted);
  EXPECT_EQ(status.history.back().next, "-> preempted");
  // A preemption requested while idle is ignored: the next run completes.
  sm.requestPreempt();
  StateMachine quick("q", {"done"});
  quick.add("A", scripted({"x"}, {"x"}), {{"x", "done"}});
  quick.requestPreempt();
  EXPECT_EQ(quick.run(data), "done");
}

TEST(StateMachine, PreemptionBetweenStatesIsCheckedBeforeTheNextState) {
  StateMachine* self = nullptr;
  int second_runs = 0;
  StateMachine sm("m", {"done"});
  self = &sm;
  sm.add("FIRST",
         std::make_unique<FunctionState>(std::vector<std::string>{"next"},
                                         [&self](UserData&, tsm::ExecutionContext&) {
                                           self->requestPreempt();
                                           return std::string("next");
                                         }),
         {{"next", "SECOND"}});
  sm.add("SECOND", scripted({"x"}, {"x"}, &second_runs), {{"x", "done"}});
  UserData data;
  EXPECT_EQ(sm.run(data), tsm::kPreempted);
  EXPECT_EQ(second_runs, 0);
}

TEST(StateMachine, PreemptionReachesNestedMachines) {
  StateMachine outer("outer", {"done"});
  auto inner = std::make_unique<StateMachine>("inner", std::vector<std::string>{"ok"});
  StateMachine* outer_ptr = &outer;
  int after = 0;
  inner->add("STOPPER",
             std::make_unique<FunctionState>(std::vector<std::string>{"go"},
                                             [outer_ptr](UserData&, tsm::ExecutionContext&) {
                                               outer_ptr->requestPreempt();
                                               return std::string("go");
                                             }),
             {{"go", "AFTER"}});
  inner->add("AFTER", scripted({"go"}, {"go"}, &after), {{"go", "ok"}});
  outer.add("SUB", std::move(inner), {{"ok", "done"}});  // inner's "preempted" falls through to outer's
  UserData data;
  EXPECT_EQ(outer.run(data), tsm::kPreempted);
  EXPECT_EQ(after, 0);
  EXPECT_EQ(outer.status().history.back().state, "SUB");
  EXPECT_EQ(outer.status().history.back().outcome, tsm::kPreempted);
}

TEST(StateMachine, RunAgainStartsFresh) {
  StateMachine sm("m", {"done"});
  sm.add("A", scripted({"x"}, {"x"}), {{"x", "done"}});
  UserData data;
  sm.run(data);
  sm.run(data);
  EXPECT_EQ(sm.status().transitions, 1u);
  EXPECT_EQ(sm.status().history.size(), 1u);
  EXPECT_EQ(sm.stateNames(), std::vector<std::string>{"A"});
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
