#include "thorvald_can_devices/device_sim.h"

#include "thorvald_can_devices/bus_error.h"

namespace thorvald_can_devices {

DeviceSim::DeviceSim(const thorvald_base::RobotConfig& config) {
  const auto& drives = config.drives;
  for (size_t i = 0; i < drives.size(); ++i) {
    const auto& d = drives[i];
    if (d.protocol == "cia402") {
      cia402_.emplace_back(d, false);
      drive_index_[d.index].push_back({1, cia402_.size() - 1});
      if (d.steered()) {
        cia402_.emplace_back(d, true);
        drive_index_[d.index].push_back({1, cia402_.size() - 1});
      }
      continue;
    }
    std::vector<thorvald_base::DriveConfig> channels{d};
    if (d.type == 1 && i + 1 < drives.size() && drives[i + 1].type == 1 && drives[i + 1].node == d.node &&
        drives[i + 1].protocol == d.protocol) {
      channels.push_back(drives[i + 1]);
    }
    thorvald_.emplace_back(channels);
    for (const auto& c : channels) drive_index_[c.index].push_back({0, thorvald_.size() - 1});
    i += channels.size() - 1;
  }
  for (const auto& b : config.batteries) {
    if (!b.present()) continue;
    battery_index_[b.name] = batteries_.size();
    batteries_.emplace_back(b);
  }
  for (const auto& io : config.io) io_.emplace_back(io);
}

void DeviceSim::spinOnce(double now_s, CanBus& bus) {
  CanFrame f;
  // Bounded like the host: a flood cannot stop the simulated devices from stepping.
  for (size_t n = 0; n < kMaxFramesPerSpin && bus.receive(&f); ++n) {
    ++frames_handled_;
    for (auto& d : thorvald_) d.handle(f, bus);
    for (auto& a : cia402_) a.handle(f, bus, now_s);
    for (auto& io : io_) io.handle(f, bus, now_s);
  }
  for (auto& d : thorvald_) d.step(now_s, bus);
  for (auto& a : cia402_) a.step(now_s, bus);
  for (auto& b : batteries_) b.step(now_s, bus);
  for (auto& io : io_) io.step(now_s, bus);
}

bool DeviceSim::inject(const std::string& target, const std::string& fault, bool active, CanBus& bus,
                       std::string* message) {
  const auto done = [&](bool ok, const std::string& text) {
    if (message) *message = text;
    return ok;
  };
  const std::string what = fault + (active ? " injected on " : " removed from ") + target;
  if (target == "bus") {
    if (fault == "bus_off") {
      bus.send(active ? makeBusOffFrame() : makeRestartedFrame());
    } else if (fault == "error_passive") {
      CanFrame f = makeErrorPassiveFrame();
      if (!active) f.data[1] = kCtrlActive;
      bus.send(f);
    } else {
      return done(false, "bus faults are bus_off and error_passive, not '" + fault + "'");
    }
    return done(true, what);
  }
  if (target.rfind("drive", 0) == 0) {
    if (fault != "silent" && fault != "stall" && fault != "encoder") {
      return done(false, "drive faults are silent, stall and encoder, not '" + fault + "'");
    }
    int index = -1;
    try {
      index = std::stoi(target.substr(5));
    } catch (...) {
    }
    auto it = drive_index_.find(index);
    if (it == drive_index_.end()) return done(false, "no drive '" + target + "' in the robot file");
    for (const auto& [kind, pos] : it->second) {
      if (kind == 0) {
        thorvald_[pos].setFault(fault, active);
      } else if (fault == "silent" || pos == it->second.front().second) {
        cia402_[pos].setFault(fault, active);  // stall/encoder act on the propulsion axis
      }
    }
    return done(true, what);
  }
  for (auto& io : io_) {
    if (io.name() != target) continue;
    if (!io.setFault(fault, active)) return done(false, "relay board faults are silent and stuck, not '" + fault + "'");
    return done(true, what);
  }
  auto b = battery_index_.find(target);
  if (b == battery_index_.end()) return done(false, "no drive, battery, relay board or 'bus' named '" + target + "'");
  if (fault != "silent" && fault != "alarm")
    return done(false, "battery faults are silent and alarm, not '" + fault + "'");
  batteries_[b->second].setFault(fault, active);
  return done(true, what);
}

}  // namespace thorvald_can_devices
