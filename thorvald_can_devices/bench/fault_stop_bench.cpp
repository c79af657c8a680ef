// Time from a fault to every drive commanded to zero, per fault kind, and control cycles missed under a flood.
// The base (CanBaseHardware + BaseDriver) and the simulated devices (DeviceSim) share one virtual bus in this
// process; fault timing runs on a simulated clock (2 ms device steps, 20 ms control cycles, faults injected at a
// random point of the cycle), the flood part on the wall clock with a second thread sending 100,000 frames/s.
//   rosrun thorvald_can_devices fault_stop_bench [--injections N] [--seed S] [--robot FILE] [--flood-seconds S]
//     [--control-rt-priority P]
#include <pthread.h>
#include <sched.h>
#include <time.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <thorvald_common/bench_statistics.h>
#include <thorvald_common/command_line.h>
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include "thorvald_base/base_driver.h"
#include "thorvald_base/standard_calculator.h"
#include "thorvald_can_devices/can_base_hardware.h"
#include "thorvald_can_devices/device_sim.h"
#include "thorvald_can_devices/virtual_can_bus.h"

using namespace thorvald_can_devices;

namespace {

struct FaultKind {
  std::string name, target, fault;
};

/// CPU time of the calling thread [s]: a cycle's own work, without the time other threads had the core.
double threadCpuS() {
  timespec ts{};
  ::clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double steadyS() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

/// One base on one bus with its simulated devices, on a clock the bench sets (`t`).
struct Base {
  Base(const thorvald_base::RobotConfig& cfg, const std::string& bus, bool wall_clock)
      : config(cfg),
        sim_bus(std::make_unique<VirtualCanBus>(bus)),
        sim(cfg),
        // On the simulated clock the devices' thread advances the time start-up waits on, faster than a loaded
        // machine may serve the CiA 402 configuration: a long start-up timeout (start-up ends as soon as every
        // device answers) keeps a slow machine from losing a drive before the first injection.
        hw(CanBaseOptions{wall_clock ? 3.0 : 60.0, "", 1000},
           wall_clock ? CanBaseHardware::Clock{} : CanBaseHardware::Clock([this] { return t.load(); })),
        wall_clock_(wall_clock) {
    if (wall_clock_) t = steadyS();
    // Start-up needs the devices to answer while initialize() waits; on the simulated clock this thread also
    // advances the time initialize() waits on, so it runs until initialize() returns (on a loaded machine that
    // takes longer than its 3 s start-up timeout in wall time).
    std::thread devices([&] {
      while (!started_) {
        if (!wall_clock_) t = t + 0.002;
        sim.spinOnce(wall_clock_ ? steadyS() : t.load(), *sim_bus);
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
      }
    });
    try {
      hw.initializeOnBus(config, std::make_unique<VirtualCanBus>(bus));
    } catch (...) {
      started_ = true;
      devices.join();
      throw;
    }
    started_ = true;
    devices.join();
    driver = std::make_unique<thorvald_base::BaseDriver>(config, std::make_unique<thorvald_base::StandardCalculator>(),
                                                         hw.takeDrives(), hw.takeBatteries(),
                                                         thorvald_base::BaseDriverOptions{});
  }
  /// `steps` device steps of 2 ms (simulated clock).
  void steps(int n) {
    for (int k = 0; k < n; ++k) {
      t = t + 0.002;
      sim.spinOnce(t, *sim_bus);
    }
  }
  void hostCycle(const thorvald_base::Twist2D& cmd) {
    hw.poll(t);
    driver->setCommand(cmd, t);
    driver->update(t);
  }
  bool allZero() const {
    for (const auto& c : driver->commands())
      if (c.wheel_speed_radps != 0.0) return false;
    return true;
  }
  void inject(const FaultKind& k, bool active) {
    std::string msg;
    if (!sim.inject(k.target, k.fault, active, *sim_bus, &msg)) std::fprintf(stderr, "inject: %s\n", msg.c_str());
  }

  thorvald_base::RobotConfig config;
  std::atomic<double> t{1000.0};
  std::unique_ptr<VirtualCanBus> sim_bus;
  DeviceSim sim;
  CanBaseHardware hw;
  std::unique_ptr<thorvald_base::BaseDriver> driver;

 private:
  bool wall_clock_;
  std::atomic<bool> started_{false};
};

using thorvald_common::percentile;

/// Fault -> all drives at zero, `injections` times; times in ms (-1 when the stop never came within 10 s).
std::vector<double> measure(const thorvald_base::RobotConfig& config, const FaultKind& kind, int injections,
                            std::mt19937& rng) {
  Base base(config, "fsb" + std::to_string(::getpid()) + "_" + kind.name, false);
  const thorvald_base::Twist2D cmd{0.5, 0.0, 0.1};
  std::vector<double> out;
  for (int i = 0; i < injections; ++i) {
    for (int c = 0; c < 50; ++c) {  // 1 s of driving
      base.steps(10);
      base.hostCycle(cmd);
    }
    if (base.allZero() || base.driver->driveStop()) {
      std::fprintf(stderr, "%s: base not driving before injection %d (%s)\n", kind.name.c_str(), i,
                   base.driver->driveStopText().c_str());
    }
    const int phase = std::uniform_int_distribution<int>(0, 9)(rng);
    base.steps(phase);
    base.inject(kind, true);
    const double t_fault = base.t;
    base.steps(10 - phase);
    base.hostCycle(cmd);
    while (!base.allZero() && base.t - t_fault < 10.0) {
      base.steps(10);
      base.hostCycle(cmd);
    }
    out.push_back(base.allZero() ? 1000.0 * (base.t - t_fault) : -1.0);
    base.inject(kind, false);
    std::string why;
    for (int c = 0; c < 150 && (base.driver->driveStop() || base.allZero()); ++c) {  // recover (up to 3 s)
      base.steps(10);
      if (base.driver->driveStop()) base.driver->clearDriveStop(&why);
      base.hostCycle(cmd);
    }
  }
  return out;
}

struct FloodResult {
  long cycles = 0, missed = 0, flood_frames = 0, drive_stops = 0;
  double max_gap_ms = 0.0, max_cycle_ms = 0.0, max_cycle_cpu_ms = 0.0;
};

/// 50 Hz control cycles on the wall clock while another endpoint floods the bus at `fps` frames per second.
FloodResult flood(const thorvald_base::RobotConfig& config, double seconds, double fps, int rt_priority) {
  const std::string bus = "fsb" + std::to_string(::getpid()) + "_flood";
  Base base(config, bus, true);
  std::atomic<bool> stop{false};
  std::atomic<long> sent{0};
  std::thread flooder([&] {
    VirtualCanBus out(bus);
    const CanFrame junk = makeFrame(0x321, {1, 2, 3, 4, 5, 6, 7, 8});
    const double start = steadyS();
    while (!stop) {
      const long due = static_cast<long>((steadyS() - start) * fps);
      while (sent < due && !stop) {
        out.send(junk);
        ++sent;
      }
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
  });
  // The devices run in a thread of their own, as can_device_sim runs in a process of its own. Real drives answer
  // on their own processors: the simulated ones step every millisecond (reading what waits, bounded) instead of
  // spinning on a flooded bus, which would take a core of this machine from the control loop being measured.
  std::thread devices([&] {
    while (!stop) {
      base.sim.spinOnce(steadyS(), *base.sim_bus);
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  });
  FloodResult r;
  // The control loop at a real-time priority, as a robot runs base_driver (e.g. launch-prefix "chrt -f 50"); the
  // flooder and the devices stay at normal priority.
  if (rt_priority > 0) {
    sched_param p{};
    p.sched_priority = rt_priority;
    const int e = ::pthread_setschedparam(::pthread_self(), SCHED_FIFO, &p);
    if (e != 0) std::fprintf(stderr, "cannot run the control loop at SCHED_FIFO %d: error %d\n", rt_priority, e);
  }
  const double period = 0.02;
  double next = steadyS(), last = -1.0;
  const double end = next + seconds;
  const thorvald_base::Twist2D cmd{0.3, 0.0, 0.0};
  bool was_stopped = false;
  while (next < end) {
    std::this_thread::sleep_until(std::chrono::steady_clock::time_point(
        std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(next))));
    const double start = steadyS();
    const double cpu_start = threadCpuS();
    base.t = start;
    base.hostCycle(cmd);
    const double done = steadyS();
    r.max_cycle_cpu_ms = std::max(r.max_cycle_cpu_ms, 1000.0 * (threadCpuS() - cpu_start));
    if (last > 0.0) {
      const double gap = start - last;
      r.max_gap_ms = std::max(r.max_gap_ms, 1000.0 * gap);
      if (gap > 1.5 * period) r.missed += static_cast<long>(gap / period - 0.5);
    }
    r.max_cycle_ms = std::max(r.max_cycle_ms, 1000.0 * (done - start));
    if (base.driver->driveStop() && !was_stopped) ++r.drive_stops;
    was_stopped = base.driver->driveStop();
    last = start;
    ++r.cycles;
    next += period;
    if (next < steadyS()) next = steadyS();  // late: do not try to catch up with a burst
  }
  if (rt_priority > 0) {
    sched_param p{};
    ::pthread_setschedparam(::pthread_self(), SCHED_OTHER, &p);
  }
  stop = true;
  flooder.join();
  devices.join();
  r.flood_frames = sent;
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"fault_stop_bench: time from a fault to every drive commanded to zero, and cycles missed under a flood"};
  int injections = 20;
  unsigned seed = 1;
  double flood_seconds = 5.0, flood_fps = 100000.0;
  std::string robot = std::string(THORVALD_CAN_DEVICES_DIR) + "/test/robots/mixed.yaml";
  app.add_option("--injections", injections, "injections per fault kind")->check(CLI::Range(1, 10000));
  app.add_option("--seed", seed, "seed of the injection phases");
  app.add_option("--robot", robot, "robot file (Thorvald and CiA 402 drives, one battery)")->check(CLI::ExistingFile);
  app.add_option("--flood-seconds", flood_seconds, "wall-clock length of the flood run [s]")
      ->check(CLI::Range(1.0, 600.0));
  app.add_option("--flood-fps", flood_fps, "flood rate [frames/s]")->check(CLI::Range(1.0, 1e7));
  int rt_priority = 0;
  app.add_option("--control-rt-priority", rt_priority,
                 "SCHED_FIFO priority of the control loop in the flood runs (0: normal scheduling)")
      ->check(CLI::Range(0, 99));
  if (const auto code = thorvald_common::parseCommandLine(app, argc, argv)) return *code;
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // progress shows when piped

  char folder[] = "/tmp/thorvald_fault_bench.XXXXXX";
  if (!::mkdtemp(folder)) return 1;
  ::setenv("THORVALD_VCAN_DIR", folder, 1);
  const auto config = thorvald_base::loadRobotConfigFile(robot);
  std::string battery = config.batteries.empty() ? "" : config.batteries.front().name;
  std::vector<FaultKind> kinds = {{"silent_drive", "drive1", "silent"},
                                  {"silent_cia402", "drive0", "silent"},
                                  {"stall", "drive2", "stall"},
                                  {"encoder", "drive1", "encoder"},
                                  {"bus_off", "bus", "bus_off"}};
  if (!battery.empty()) {
    kinds.push_back({"battery_over_temperature", battery, "alarm"});
    kinds.push_back({"lost_battery", battery, "silent"});
  }
  std::mt19937 rng(seed);
  std::printf("%-26s %6s %10s %10s %10s %8s\n", "fault", "n", "p50 [ms]", "p99 [ms]", "max [ms]", "missed");
  std::fflush(stdout);
  std::string json;
  for (const auto& k : kinds) {
    const auto ms = measure(config, k, injections, rng);
    std::vector<double> ok;
    for (double v : ms)
      if (v >= 0.0) ok.push_back(v);
    const double p50 = percentile(ok, 0.5), p99 = percentile(ok, 0.99), mx = percentile(ok, 1.0);
    std::printf("%-26s %6zu %10.1f %10.1f %10.1f %8zu\n", k.name.c_str(), ms.size(), p50, p99, mx,
                ms.size() - ok.size());
    std::fflush(stdout);
    char buf[160];
    std::snprintf(buf, sizeof(buf), "\"%s_stop_p50_ms\": %.1f, \"%s_stop_p99_ms\": %.1f, ", k.name.c_str(), p50,
                  k.name.c_str(), p99);
    json += buf;
  }
  // The same wall-clock run without a flood first: on a loaded machine cycles are missed anyway, and only the
  // difference is the flood's doing.
  const FloodResult quiet = flood(config, flood_seconds, 0.0, rt_priority);
  std::printf(
      "no flood: %ld control cycles, %ld missed, longest gap %.1f ms, longest cycle %.2f ms (CPU %.2f ms), %ld drive "
      "stops\n",
      quiet.cycles, quiet.missed, quiet.max_gap_ms, quiet.max_cycle_ms, quiet.max_cycle_cpu_ms, quiet.drive_stops);
  const FloodResult f = flood(config, flood_seconds, flood_fps, rt_priority);
  std::printf(
      "flood: %ld frames in %.0f s, %ld control cycles, %ld missed, longest gap %.1f ms, longest cycle %.2f ms (CPU "
      "%.2f ms), %ld drive stops\n",
      f.flood_frames, flood_seconds, f.cycles, f.missed, f.max_gap_ms, f.max_cycle_ms, f.max_cycle_cpu_ms,
      f.drive_stops);
  std::printf(
      "RESULT {%s\"flood_missed_cycles\": %ld, "
      "\"flood_max_cycle_gap_ms\": %.1f, \"flood_max_cycle_cpu_ms\": %.2f, \"flood_drive_stops\": %ld, "
      "\"flood_frames_per_s\": %.0f, "
      "\"no_flood_missed_cycles\": %ld, \"no_flood_max_cycle_gap_ms\": %.1f}\n",
      json.c_str(), f.missed, f.max_gap_ms, f.max_cycle_cpu_ms, f.drive_stops, f.flood_frames / flood_seconds,
      quiet.missed, quiet.max_gap_ms);
  ::rmdir(folder);
  return 0;
}
