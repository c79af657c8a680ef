// Unit tests of what the uv_mission node runs the mission with, ROS-free: the runner behind ~start and ~stop, the
// mission's files (targets from the rail-set file, progress file, report) and the cruise speed of the report.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "greenhouse_rail_nav/rail_run.h"
#include "greenhouse_rail_nav/uv_mission_files.h"
#include "greenhouse_rail_nav/uv_mission_runner.h"

namespace grn = greenhouse_rail_nav;

namespace {

/// A robot standing on the headland floor whose navigation never arrives (or whose navigation goal throws).
/// Called on the mission's thread; the test thread polls the atomics only.
class WaitingRobot : public grn::MissionIO {
 public:
  bool throw_on_goal = false;
  std::atomic<int> goals{0};
  std::vector<std::string> events;  ///< read after the runner's thread has ended

  double now() override { return t_; }
  bool ok() override { return true; }
  void waitTick() override {
    t_ += 0.02;
    std::this_thread::sleep_for(std::chrono::microseconds(200));  // pacing, not synchronisation
  }
  void sendNavGoal(const thorvald_base::Pose2D&) override {
    ++goals;
    if (throw_on_goal) throw std::runtime_error("navigation interface broken");
  }
  grn::NavState navState(std::string*) override { return grn::NavState::kActive; }
  void cancelNav() override { events.push_back("cancel"); }
  bool odomPose(thorvald_base::Pose2D* p) override {
    *p = thorvald_base::Pose2D();
    return true;
  }
  bool mapPose(thorvald_base::Pose2D* p) override { return odomPose(p); }
  grn::RailObservation railObservation() override { return {}; }
  grn::SurfaceReading surface() override { return {grn::Surface::kFloor, grn::Surface::kFloor, t_}; }
  double forwardRange() override { return NAN; }
  bool safetyStopped(std::string*) override { return false; }
  void commandTwist(double v, double w) override { events.push_back(v == 0.0 && w == 0.0 ? "stop" : "move"); }
  void setLights(bool on) override { events.push_back(on ? "lights on" : "lights off"); }
  void resetLocalisation(const thorvald_base::Pose2D&) override {}
  void log(const std::string&) override {}

 private:
  double t_ = 0.0;
};

/// What the runner's hooks saw.
struct HookLog {
  std::mutex mutex;
  std::vector<std::string> outcomes, errors;
  std::atomic<int> finished{0}, exits{0};

  grn::UvMissionRunner::Hooks hooks(WaitingRobot* robot) {
    grn::UvMissionRunner::Hooks h;
    h.error = [this, robot](const std::string& e) {
      std::lock_guard<std::mutex> l(mutex);
      errors.push_back(e);
      robot->events.push_back("error");
    };
    h.finished = [this](const std::string& outcome) {
      std::lock_guard<std::mutex> l(mutex);
      outcomes.push_back(outcome);
      ++finished;
    };
    h.exit = [this] { ++exits; };
    return h;
  }
};

template <typename Condition>
bool waitUntil(Condition c, double timeout_s = 10.0) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (!c()) {
    if (std::chrono::steady_clock::now() > deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

std::vector<grn::MissionTarget> oneTarget() {
  grn::MissionTarget t;
  t.index = 4;
  t.target_pose = thorvald_base::Pose2D(-1.0, 3.2, 0.0);
  return {t};
}

grn::UvMissionParams patientParams() {
  grn::UvMissionParams p;
  p.nav_timeout_s = 1e6;  // the navigation is only ever stopped by the operator here
  return p;
}

}  // namespace

TEST(UvMissionRunner, AMissionWithNothingToDoEndsDoneAndEndsTheProcessWhenAsked) {
  for (const bool exit_when_done : {false, true}) {
    WaitingRobot robot;
    grn::UvMission mission(robot, patientParams(), {});
    HookLog log;
    grn::UvMissionRunner runner(mission, robot, exit_when_done, log.hooks(&robot));
    EXPECT_EQ(runner.start(), "started");
    ASSERT_TRUE(waitUntil([&] { return log.finished == 1 && !runner.running(); }));
    runner.shutdown();
    EXPECT_EQ(log.outcomes, std::vector<std::string>{"done"});
    EXPECT_TRUE(log.errors.empty());
    EXPECT_EQ(log.exits, exit_when_done ? 1 : 0);
  }
}

TEST(UvMissionRunner, StartsOnceStopsByPreemptionAndResumesOnTheNextStart) {
  WaitingRobot robot;
  grn::UvMission mission(robot, patientParams(), oneTarget());
  HookLog log;
  grn::UvMissionRunner runner(mission, robot, true, log.hooks(&robot));
  bool was_running = true;
  EXPECT_EQ(runner.stop(&was_running), "not running");
  EXPECT_FALSE(was_running);

  EXPECT_EQ(runner.start(), "started");
  ASSERT_TRUE(waitUntil([&] { return robot.goals >= 1; }));
  EXPECT_TRUE(runner.running());
  EXPECT_EQ(runner.start(), "already running");
  EXPECT_EQ(runner.stop(&was_running), "stopping; ~start resumes at the first rail set not treated");
  EXPECT_TRUE(was_running);
  ASSERT_TRUE(waitUntil([&] { return log.finished == 1 && !runner.running(); }));
  EXPECT_EQ(log.outcomes.back(), thorvald_state_machine::kPreempted);
  EXPECT_EQ(log.exits, 0) << "a preempted run does not end the process";

  EXPECT_EQ(runner.start(), "started");
  ASSERT_TRUE(waitUntil([&] { return robot.goals >= 2; }));
  runner.shutdown();
  EXPECT_EQ(log.finished, 2);
  EXPECT_EQ(log.outcomes.back(), thorvald_state_machine::kPreempted);
  EXPECT_EQ(log.exits, 0);
  EXPECT_FALSE(runner.running());
  EXPECT_EQ(runner.start(), "shutting down");
}

TEST(UvMissionRunner, ARunThatThrowsIsAbortedWithTheRobotStoppedAndItsLightsOff) {
  WaitingRobot robot;
  robot.throw_on_goal = true;
  grn::UvMission mission(robot, patientParams(), oneTarget());
  HookLog log;
  grn::UvMissionRunner runner(mission, robot, true, log.hooks(&robot));
  EXPECT_EQ(runner.start(), "started");
  ASSERT_TRUE(waitUntil([&] { return log.finished == 1 && !runner.running(); }));
  runner.shutdown();
  EXPECT_EQ(log.outcomes, std::vector<std::string>{"aborted"});
  EXPECT_EQ(log.errors, std::vector<std::string>{"navigation interface broken"});
  ASSERT_GE(robot.events.size(), 3u);
  const std::vector<std::string> last(robot.events.end() - 3, robot.events.end());
  EXPECT_EQ(last, (std::vector<std::string>{"error", "stop", "lights off"}));
  EXPECT_EQ(log.exits, 1) << "an aborted run ends the process with exit_when_done";
}

TEST(UvMissionFiles, TargetsKeepTheFileOrderAndTheAnalyzersVerdict) {
  grn::RailSetFile file;
  for (int i : {2, 0, 1}) {
    grn::RailSetEstimate e;
    e.index = i;
    e.target_pose = thorvald_base::Pose2D(0.5 * i, 1.6 * i, 0.01 * i);
    e.good = i != 1;
    e.reason = e.good ? "" : "spacing irregular";
    file.rail_sets.push_back(e);
  }
  const auto targets = grn::missionTargets(file);
  ASSERT_EQ(targets.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    const auto& e = file.rail_sets[k];
    EXPECT_EQ(targets[k].index, e.index);
    EXPECT_EQ(targets[k].target_pose.x, e.target_pose.x);
    EXPECT_EQ(targets[k].target_pose.y, e.target_pose.y);
    EXPECT_EQ(targets[k].target_pose.yaw, e.target_pose.yaw);
    EXPECT_EQ(targets[k].good, e.good);
    EXPECT_EQ(targets[k].note, e.reason);
  }
  EXPECT_TRUE(grn::missionTargets(grn::RailSetFile()).empty());
}

TEST(UvMissionFiles, ProgressIsWrittenAndReadBack) {
  const std::string path = ::testing::TempDir() + "uv_mission_progress_test.yaml";
  std::remove(path.c_str());
  EXPECT_TRUE(grn::loadProgress(path).empty()) << "no file yet";
  EXPECT_TRUE(grn::loadProgress("").empty());
  grn::saveProgress(path, {5, 0, 2});
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(),
            "# Rail sets the UV mission has treated; a restarted mission skips them. Delete to start over.\n"
            "treated: [0, 2, 5]\n");
  EXPECT_EQ(grn::loadProgress(path), (std::set<int>{0, 2, 5}));
  grn::saveProgress(path, {});
  EXPECT_TRUE(grn::loadProgress(path).empty());
  std::ofstream(path) << "something: else\n";
  EXPECT_TRUE(grn::loadProgress(path).empty()) << "no treated list";
  std::remove(path.c_str());
}

TEST(UvMissionFiles, TheReportHasAHeaderAndOneLinePerRailSet) {
  grn::RailSetReport a;
  a.index = 3;
  a.treated = true;
  a.result = "treated";
  a.entry_attempts = 1;
  a.rail_length_m = 19.25;
  a.lights_on_s = 40.5;
  a.speed_mean_mps = 0.49;
  a.speed_std_mps = 0.01;
  a.duration_s = 120.0;
  a.lit_pct = 100.0;
  a.pauses = 1;
  grn::RailSetReport b;
  b.index = 4;
  b.result = "rails not found by the search";
  b.searches = 1;
  EXPECT_EQ(grn::reportCsv({a, b}),
            "rail_set,treated,result,align_attempts,entry_attempts,searches,rail_length_m,lights_on_s,speed_mean_mps,"
            "speed_std_mps,duration_s,lit_pct,pauses\n"
            "3,1,\"treated\",0,1,0,19.25,40.5,0.49,0.01,120,100,1\n"
            "4,0,\"rails not found by the search\",0,0,1,0,0,0,0,0,0,0\n");
}

TEST(CruiseSpeedMeter, MeasuresOverWindowsSoTheOdometryRateDoesNotShowInTheSpread) {
  // Odometry every third control tick of 20 ms: per tick the robot seems to stand still or to do 1.5 m/s.
  grn::CruiseSpeedMeter meter;
  for (int i = 0; i < 600; ++i) meter.add(true, i % 3 == 2 ? 0.03 : 0.0, 0.02);
  double mean = -1.0, sd = -1.0;
  ASSERT_TRUE(meter.stats(&mean, &sd));
  EXPECT_GE(meter.windows(), 20);
  EXPECT_LE(meter.windows(), 24);
  EXPECT_NEAR(mean, 0.5, 0.03);
  EXPECT_LT(sd, 0.05);
}

TEST(CruiseSpeedMeter, TicksOffCruiseOrWithoutTimeDropTheOpenWindow) {
  grn::CruiseSpeedMeter meter(0.5);
  double mean = 7.0, sd = 7.0;
  EXPECT_FALSE(meter.stats(&mean, &sd));
  EXPECT_EQ(mean, 7.0) << "untouched without a window";
  meter.add(true, 0.2, 0.4);
  meter.add(false, 0.05, 0.1);  // braking: the 0.4 s so far do not count
  meter.add(true, 0.2, 0.4);
  EXPECT_EQ(meter.windows(), 0);
  meter.add(true, 0.0, 0.0);  // no time passed (a repeated clock reading)
  meter.add(true, 0.2, 0.4);
  EXPECT_EQ(meter.windows(), 0);
  meter.add(true, 0.1, 0.1);
  EXPECT_EQ(meter.windows(), 1);
  ASSERT_TRUE(meter.stats(&mean, &sd));
  EXPECT_NEAR(mean, 0.3 / 0.5, 1e-12);
  EXPECT_NEAR(sd, 0.0, 1e-6);
  meter.add(true, 0.25, 0.5);
  ASSERT_TRUE(meter.stats(&mean, &sd));
  EXPECT_NEAR(mean, 0.55, 1e-12);
  EXPECT_NEAR(sd, 0.05, 1e-9);
}
