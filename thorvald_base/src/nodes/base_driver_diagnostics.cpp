// base_driver's diagnostics: the base (stop reason, cycle timing, bus and relay counters), drives and batteries.
#include <cmath>
#include <string>

#include "base_driver_ros.h"

namespace thorvald_base {

void BaseDriverRos::diagnoseBase(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  using diagnostic_msgs::DiagnosticStatus;
  const StopReason reason = driver_->stopReason();
  if (reason == StopReason::kDriveStop) {
    stat.summary(DiagnosticStatus::ERROR, "propulsion stopped: " + driver_->driveStopText());
  } else if (reason == StopReason::kSafetyStop) {
    stat.summary(DiagnosticStatus::WARN, "safety stop engaged");
  } else if (reason == StopReason::kBatteryStop) {
    stat.summary(DiagnosticStatus::ERROR, "propulsion stopped by the battery policy: " + driver_->batteryText());
  } else if (hardware_ && !hardware_->busOk()) {
    stat.summary(DiagnosticStatus::ERROR, "bus not usable");
  } else {
    stat.summary(DiagnosticStatus::OK, toString(reason));
  }
  bool wheels_turn = false;
  for (const auto& fb : driver_->feedback()) wheels_turn = wheels_turn || std::fabs(fb.wheel_speed_radps) > 1e-3;
  if (wheels_turn && !driver_->velocity().valid) {
    stat.mergeSummary(DiagnosticStatus::ERROR,
                      "odometry cannot resolve the motion: the wheels turn but too few of them report to determine "
                      "(vx, vy, wz)");
  }
  stat.add("mode", simple_sim_ ? "simulation" : "hardware");
  stat.add("kinematics", driver_->calculator().name());
  stat.add("cycle rate [Hz]", cycle_rate_hz_);
  stat.add("longest cycle gap since last report [ms]", 1000.0 * gap_max_window_s_);
  stat.add("longest cycle gap [ms]", 1000.0 * gap_max_total_s_);
  stat.add("missed cycles", missed_cycles_);
  stat.add("longest cycle since last report [ms]", 1000.0 * cycle_work_max_window_s_);
  stat.add("longest command wait in the queue since last report [ms]", 1000.0 * cmd_wait_max_window_s_);
  cycle_work_max_window_s_ = cmd_wait_max_window_s_ = 0.0;
  stat.add("commands written through", write_throughs_);
  stat.add("wheel limit factor", driver_->wheelFactor());
  if (!driver_->batteryText().empty()) stat.add("battery policy", driver_->batteryText());
  if (gap_max_window_s_ > 3.0 * period_s_) {
    stat.mergeSummary(
        diagnostic_msgs::DiagnosticStatus::WARN,
        "control cycle stalled for " + std::to_string(static_cast<int>(1000.0 * gap_max_window_s_)) + " ms");
  }
  gap_max_window_s_ = 0.0;
  stat.add("cycles", driver_->cycles());
  stat.add("rejected commands", driver_->rejectedCommands());
  stat.add("distance travelled [m]", driver_->odometry().distance());
  if (hardware_) {
    for (const auto& kv : hardware_->diagnostics()) stat.add(kv.first, kv.second);
    if (relay_) relay_->diagnose(stat);
  }
}

void BaseDriverRos::diagnoseDrives(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  using diagnostic_msgs::DiagnosticStatus;
  int bad = 0;
  for (size_t i = 0; i < driver_->driveStatus().size(); ++i) {
    const auto& s = driver_->driveStatus()[i];
    const bool ok = s.online && !s.fault;
    bad += ok ? 0 : 1;
    stat.add("drive" + std::to_string(i), describe(s));
  }
  if (bad) {
    stat.summary(DiagnosticStatus::ERROR, std::to_string(bad) + " drive(s) lost or faulted");
  } else {
    stat.summary(DiagnosticStatus::OK, "all drives ok");
  }
}

void BaseDriverRos::diagnoseBatteries(diagnostic_updater::DiagnosticStatusWrapper& stat) {
  using diagnostic_msgs::DiagnosticStatus;
  stat.summary(DiagnosticStatus::OK, "batteries ok");
  if (!driver_->batteryText().empty()) {
    stat.mergeSummary(
        driver_->stopReason() == StopReason::kBatteryStop ? DiagnosticStatus::ERROR : DiagnosticStatus::WARN,
        driver_->batteryText());
  }
  const auto readings = driver_->batteries();
  for (size_t i = 0; i < readings.size(); ++i) {
    const auto& r = readings[i];
    const std::string name = driver_->batteryDevices()[i]->name();
    const std::string stale = r.online ? "" : " (stale)";
    stat.add(name + " voltage [V]" + stale, r.voltage_v);
    stat.add(name + " charge [%]" + stale, r.charge_pct);
    if (r.age_s >= 0.0) stat.add(name + " last heard [s ago]", r.age_s);
    if (!r.online) stat.mergeSummary(DiagnosticStatus::ERROR, name + " not heard from: values are stale");
    if (r.alarms) stat.mergeSummary(DiagnosticStatus::WARN, name + " reports alarms");
  }
}

}  // namespace thorvald_base
