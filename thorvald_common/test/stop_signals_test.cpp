#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <stdexcept>
#include <thread>

#include "thorvald_common/stop_signals.h"

using thorvald_common::StopSignals;

namespace {

std::atomic<int> g_calls{0};
void countCall() { ++g_calls; }

/// Runs `body` in a child process; returns its exit status and how long it took [s].
template <typename Body>
std::pair<int, double> inChild(Body body) {
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = fork();
  if (pid == 0) {
    body();
    _exit(42);  // the body should never return
  }
  int status = 0;
  waitpid(pid, &status, 0);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return {status, seconds};
}

}  // namespace

TEST(StopSignals, SignalSetsTheFlagAndCallsTheHook) {
  g_calls = 0;
  {
    StopSignals stop(countCall, 5.0);
    EXPECT_FALSE(StopSignals::requested());
    std::raise(SIGTERM);
    EXPECT_TRUE(StopSignals::requested());
    EXPECT_EQ(g_calls, 1);
    stop.setOnSignal(nullptr);
    std::raise(SIGINT);
    EXPECT_EQ(g_calls, 1);  // the flag alone now
  }                         // finished within the grace: the watchdog leaves the process alone
  // Handlers are back to the defaults; a second instance may be created.
  StopSignals again(countCall, 5.0);
  EXPECT_FALSE(StopSignals::requested());
}

TEST(StopSignals, RefusesBadArguments) {
  EXPECT_THROW(StopSignals(countCall, 0.0), std::invalid_argument);
  StopSignals one(countCall, 1.0);
  EXPECT_THROW(StopSignals(countCall, 1.0), std::logic_error);
}

TEST(StopSignals, WatchdogEndsAProcessStuckAfterTheSignal) {
  const auto [status, seconds] = inChild([] {
    StopSignals stop(nullptr, 0.2);
    std::raise(SIGTERM);
    std::this_thread::sleep_for(std::chrono::seconds(30));  // stuck, as in a request to a silent master
  });
  ASSERT_TRUE(WIFEXITED(status)) << status;
  EXPECT_EQ(WEXITSTATUS(status), 0);
  EXPECT_GE(seconds, 0.2);
  EXPECT_LT(seconds, 5.0);  // generous for a loaded machine; the node-level test asserts 1 s
}

TEST(StopSignals, NoSignalNoWatchdog) {
  const auto [status, seconds] = inChild([] {
    {
      StopSignals stop(nullptr, 0.05);
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
    _exit(7);  // the watchdog did not end the process
  });
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 7);
  (void)seconds;
}
