#include "greenhouse_rail_nav/uv_mission_runner.h"

#include <exception>

namespace greenhouse_rail_nav {

UvMissionRunner::UvMissionRunner(UvMission& mission, MissionIO& io, bool exit_when_done, Hooks hooks)
    : mission_(mission), io_(io), exit_when_done_(exit_when_done), hooks_(std::move(hooks)) {}

UvMissionRunner::~UvMissionRunner() { shutdown(); }

std::string UvMissionRunner::start() {
  std::lock_guard<std::mutex> l(worker_mutex_);
  if (shut_down_) return "shutting down";
  if (running_) return "already running";
  if (worker_.joinable()) worker_.join();
  running_ = true;
  worker_ = std::thread([this] { runOnce(); });
  return "started";
}

std::string UvMissionRunner::stop(bool* was_running) {
  mission_.requestPreempt();
  *was_running = running_;
  return *was_running ? "stopping; ~start resumes at the first rail set not treated" : "not running";
}

void UvMissionRunner::shutdown() {
  mission_.requestPreempt();
  std::lock_guard<std::mutex> l(worker_mutex_);
  shut_down_ = true;
  if (worker_.joinable()) worker_.join();
}

void UvMissionRunner::runOnce() {
  std::string outcome;
  try {
    outcome = mission_.run();
  } catch (const std::exception& e) {
    outcome = "aborted";
    if (hooks_.error) hooks_.error(e.what());
    io_.commandTwist(0.0, 0.0);
    io_.setLights(false);
  }
  if (hooks_.finished) hooks_.finished(outcome);
  running_ = false;
  if (exit_when_done_ && outcome != thorvald_state_machine::kPreempted && hooks_.exit) hooks_.exit();
}

}  // namespace greenhouse_rail_nav
