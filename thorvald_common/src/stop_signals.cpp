#include "thorvald_common/stop_signals.h"

#include <fcntl.h>
#include <poll.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <stdexcept>

namespace thorvald_common {
namespace {

// What the signal handler may touch: lock-free atomics and a pipe (write() is async-signal-safe).
std::atomic<bool> g_requested{false};
std::atomic<void (*)()> g_on_signal{nullptr};
int g_pipe[2] = {-1, -1};  // written by the handler and by the destructor, read by the watchdog

void onSignal(int) {
  const int saved_errno = errno;
  g_requested = true;
  if (void (*f)() = g_on_signal.load()) f();
  const char byte = 1;
  [[maybe_unused]] const ssize_t n = write(g_pipe[1], &byte, 1);  // a full pipe already holds a wake-up
  errno = saved_errno;
}

}  // namespace

StopSignals::StopSignals(void (*on_signal)(), double grace_s) : grace_s_(grace_s) {
  if (!(grace_s > 0.0)) throw std::invalid_argument("StopSignals: grace must be > 0 s");
  if (g_pipe[0] >= 0) throw std::logic_error("StopSignals: only one instance per process");
  if (pipe2(g_pipe, O_CLOEXEC | O_NONBLOCK) != 0) throw std::runtime_error("StopSignals: cannot create a pipe");
  g_requested = false;
  g_on_signal = on_signal;
  watchdog_ = std::thread([this] { watch(); });
  struct sigaction action {};
  action.sa_handler = onSignal;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

StopSignals::~StopSignals() {
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    finished_ = true;
  }
  finished_cv_.notify_all();
  const char byte = 0;
  [[maybe_unused]] const ssize_t n = write(g_pipe[1], &byte, 1);
  watchdog_.join();
  close(g_pipe[0]);
  close(g_pipe[1]);
  g_pipe[0] = g_pipe[1] = -1;
  g_on_signal = nullptr;
}

bool StopSignals::requested() { return g_requested; }

void StopSignals::setOnSignal(void (*on_signal)()) { g_on_signal = on_signal; }

void StopSignals::watch() {
  // Wait for a signal or the end of the process's orderly life.
  while (true) {
    pollfd pfd{g_pipe[0], POLLIN, 0};
    if (poll(&pfd, 1, -1) < 0 && errno != EINTR) return;
    char buffer[16];
    while (read(g_pipe[0], buffer, sizeof(buffer)) > 0) {
    }
    std::unique_lock<std::mutex> lock(mutex_);
    if (finished_) return;
    if (g_requested) break;
  }
  std::unique_lock<std::mutex> lock(mutex_);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(grace_s_);
  if (finished_cv_.wait_until(lock, deadline, [this] { return finished_; })) return;
  std::fprintf(stderr,
               "stopping: not finished %.1f s after the signal (stuck in a call, e.g. to a master that does "
               "not answer); exiting now\n",
               grace_s_);
  std::fflush(stderr);
  _exit(0);
}

}  // namespace thorvald_common
