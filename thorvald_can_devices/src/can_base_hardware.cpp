#include "thorvald_can_devices/can_base_hardware.h"

#include <chrono>
#include <cstdio>
#include <thread>

#include "thorvald_can_devices/candump_log.h"
#include "thorvald_can_devices/canopen_protocol.h"
#include "thorvald_can_devices/cia401_board.h"
#include "thorvald_can_devices/cia402_drive.h"
#include "thorvald_can_devices/thorvald_battery.h"
#include "thorvald_can_devices/thorvald_drive.h"

namespace thorvald_can_devices {
namespace {
std::string hexId(uint32_t id) {
  char buf[16];
  std::snprintf(buf, sizeof(buf), "0x%03X", id);
  return buf;
}
}  // namespace

CanBaseHardware::CanBaseHardware(CanBaseOptions options, Clock clock) : options_(std::move(options)), clock_(clock) {
  if (!clock_) {
    clock_ = [] { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); };
  }
}

CanBaseHardware::~CanBaseHardware() = default;

void CanBaseHardware::initialize(const thorvald_base::RobotConfig& config, const std::string& interface_type,
                                 const std::string& interface_name) {
  std::unique_ptr<CanBus> bus = openCanBus(interface_type, interface_name);
  if (!options_.log_path.empty()) {
    bus = std::make_unique<LoggingCanBus>(std::move(bus), options_.log_path,
                                          interface_type == "virtual" ? "vcan_" + interface_name : interface_name);
  }
  initializeOnBus(config, std::move(bus));
}

void CanBaseHardware::addDevice(std::shared_ptr<CanDevice> device, const std::string& source) {
  for (uint32_t id : device->receiveIds()) {
    if (owned_ids_.count(id)) {
      throw thorvald_base::ConfigError(source, device->label(),
                                       "CAN id " + hexId(id) + " is already used by another device of the base");
    }
    own(id, device->label());
    routes_[id] = device.get();
  }
  for (uint32_t id : device->transmitIds()) own(id, device->label());
  devices_.push_back(std::move(device));
}

void CanBaseHardware::own(uint32_t id, const std::string& user) {
  owned_ids_.insert(id);
  id_users_.emplace(id, user);
}

std::string CanBaseHardware::canIdUser(uint32_t id) const {
  const auto it = id_users_.find(id);
  return it == id_users_.end() ? "" : it->second;
}

void CanBaseHardware::initializeOnBus(const thorvald_base::RobotConfig& config, std::unique_ptr<CanBus> bus) {
  bus_ = std::move(bus);
  owned_ids_.clear();
  id_users_.clear();
  own(canopen_ids::kNmt, "NMT");
  own(canopen_ids::kSync, "SYNC");
  own(canopen_ids::kHeartbeat + kHostNode, "the base's own heartbeat");
  const auto& drives = config.drives;
  for (size_t i = 0; i < drives.size(); ++i) {
    const auto& d = drives[i];
    if (d.protocol == "cia402") {
      has_cia402_ = true;
      std::vector<std::shared_ptr<Cia402Axis>> axes;
      for (const auto& setup : Cia402Drive::axesFor(d)) {
        if (setup.node < 1 || setup.node > 126) {
          throw thorvald_base::ConfigError(config.source, "motor_drives.drive" + std::to_string(d.index) + ".node",
                                           "CiA 402 axis node " + std::to_string(setup.node) +
                                               " outside 1..126 (a steered drive's steering axis is node + 64)");
        }
        axes.push_back(std::make_shared<Cia402Axis>(bus_.get(), setup));
        axes.back()->setFeedbackTimeout(options_.feedback_timeout_s);
        cia402_axes_.push_back(axes.back().get());
        addDevice(axes.back(), config.source);
      }
      drives_.push_back(std::make_unique<Cia402Drive>(d, axes[0], axes.size() > 1 ? axes[1] : nullptr));
      continue;
    }
    if (d.node < 1 || d.node > 127) {
      throw thorvald_base::ConfigError(config.source, "motor_drives.drive" + std::to_string(d.index) + ".node",
                                       "must be a CAN node id 1..127");
    }
    std::vector<thorvald_base::DriveConfig> channels{d};
    if (d.type == 1 && i + 1 < drives.size() && drives[i + 1].type == 1 && drives[i + 1].node == d.node &&
        drives[i + 1].protocol == d.protocol) {
      channels.push_back(drives[i + 1]);  // a two-channel propulsion pair on one controller
    }
    auto controller = std::make_shared<ThorvaldController>(bus_.get(), channels);
    controller->setFeedbackTimeout(options_.feedback_timeout_s);
    addDevice(controller, config.source);
    for (size_t c = 0; c < channels.size(); ++c) drives_.push_back(std::make_unique<ThorvaldDrive>(controller, c));
    i += channels.size() - 1;
  }
  for (const auto& b : config.batteries) {
    if (!b.present()) continue;
    if (b.id > battery_ids::kMaxId) {
      throw thorvald_base::ConfigError(config.source, "batteries." + b.name + ".id", "must be 0..15 on the CAN bus");
    }
    auto battery = std::make_shared<ThorvaldBattery>(b);
    addDevice(battery, config.source);
    // The base driver owns the Battery; the device list keeps the same object for routing.
    struct Handle : thorvald_base::Battery {
      std::shared_ptr<ThorvaldBattery> b;
      const std::string& name() const override { return b->name(); }
      void update(double now_s) override { b->update(now_s); }
      thorvald_base::BatteryReading reading() const override { return b->reading(); }
    };
    auto handle = std::make_unique<Handle>();
    handle->b = battery;
    batteries_.push_back(std::move(handle));
  }
  addIoBoards(config);

  // Start-up: bring every device to operation, then say which did not answer.
  const double t0 = now();
  for (auto& d : devices_) d->start(t0);
  while (true) {
    const double t = now();
    poll(t);
    bool all = true;
    for (auto& d : devices_) all = all && d->operational();
    if (all || t - t0 >= options_.startup_timeout_s) break;
    bus_->waitReadable(0.01);
  }
  not_answering_.clear();
  for (auto& d : devices_) {
    if (!d->operational()) not_answering_.push_back(d->label());
  }
}

std::vector<std::unique_ptr<thorvald_base::MotorDrive>> CanBaseHardware::takeDrives() { return std::move(drives_); }
std::vector<std::unique_ptr<thorvald_base::Battery>> CanBaseHardware::takeBatteries() { return std::move(batteries_); }
std::vector<std::unique_ptr<thorvald_base::IoBoard>> CanBaseHardware::takeIoBoards() { return std::move(io_boards_); }

void CanBaseHardware::addIoBoards(const thorvald_base::RobotConfig& config) {
  for (const auto& io : config.io) {
    if (io.id < 1 || io.id > 127) {
      throw thorvald_base::ConfigError(config.source, "io." + io.name + ".id", "must be a CANopen node id 1..127");
    }
    auto board = std::make_shared<Cia401Board>(bus_.get(), io);
    addDevice(board, config.source);
    // base_driver owns the IoBoard; the device list keeps the same object for routing.
    struct Handle : thorvald_base::IoBoard {
      std::shared_ptr<Cia401Board> b;
      const std::string& name() const override { return b->name(); }
      int outputCount() const override { return b->outputCount(); }
      void command(int output, bool on) override { b->command(output, on); }
      void update(double now_s) override { b->update(now_s); }
      thorvald_base::IoBoardStatus status() const override { return b->status(); }
    };
    auto handle = std::make_unique<Handle>();
    handle->b = board;
    io_boards_.push_back(std::move(handle));
  }
}

void CanBaseHardware::readBus(double now_s) {
  CanFrame f;
  for (size_t n = 0;; ++n) {
    if (n >= options_.max_frames_per_poll) {
      if (bus_->waitReadable(0.0)) {
        ++read_bound_hits_;
        const long waiting = bus_->framesWaiting();
        frames_past_bound_ += waiting > 0 ? static_cast<unsigned long>(waiting) : 1;
      }
      break;
    }
    if (!bus_->receive(&f)) break;
    if (!f.isExtended() && !f.isRemote()) {
      auto it = routes_.find(f.stdId());
      if (it != routes_.end()) {
        it->second->handle(f, now_s);
        continue;
      }
      if (owned_ids_.count(f.stdId())) continue;  // a base id sent by someone else: not for the relay
    }
    thorvald_base::CanFrameData r;
    r.id = f.id;
    r.length = f.length;
    r.data = f.data;
    relay_.push_back(r);
    if (relay_.size() > options_.relay_queue_limit) {
      relay_.pop_front();
      ++relay_overflow_;
    }
  }
}

void CanBaseHardware::poll(double) {
  const double t = now();
  if (has_cia402_) {
    if (t - last_sync_s_ >= kMinSyncPeriodS) {
      last_sync_s_ = t;
      bus_->send(encodeSync());  // the CiA 402 drives answer with their TPDOs
      for (auto* axis : cia402_axes_) axis->syncSent();
    }
    if (t - last_host_heartbeat_s_ >= kHostHeartbeatPeriodS) {
      last_host_heartbeat_s_ = t;
      bus_->send(makeFrame(canopen_ids::kHeartbeat + kHostNode, {0x05}));
    }
  }
  readBus(t);
  const bool ok = busOk();
  if (!ok && was_bus_ok_) ++bus_off_events_;
  was_bus_ok_ = ok;
  for (auto& d : devices_) {
    d->setBusOff(!ok);
    d->tick(t);
  }
}

std::vector<thorvald_base::CanFrameData> CanBaseHardware::takeRelayFrames() {
  std::vector<thorvald_base::CanFrameData> out(relay_.begin(), relay_.end());
  relay_.clear();
  return out;
}

bool CanBaseHardware::sendRelayFrame(const thorvald_base::CanFrameData& frame, std::string* why) {
  const auto refuse = [&](const std::string& reason) {
    if (why) *why = reason;
    return false;
  };
  if (frame.length > 8) return refuse("length " + std::to_string(frame.length) + " above 8");
  if (frame.id > kCanStdMask) return refuse("id " + hexId(frame.id) + " is not an 11-bit identifier");
  if (frame.id == canopen_ids::kNmt) return refuse("NMT frames are reserved to the base");
  if (frame.id == canopen_ids::kSync) return refuse("SYNC frames are reserved to the base");
  if (owned_ids_.count(frame.id)) return refuse("id " + hexId(frame.id) + " belongs to a base device");
  CanFrame f;
  f.id = frame.id;
  f.length = frame.length;
  f.data = frame.data;
  if (!bus_->send(f)) return refuse("bus send failed: " + bus_->status().last_error);
  return true;
}

unsigned long CanBaseHardware::malformedFrames() const {
  unsigned long n = 0;
  for (const auto& d : devices_) n += d->malformed();
  return n;
}

bool CanBaseHardware::busOk() const { return bus_ && bus_->status().ok; }

std::vector<std::pair<std::string, std::string>> CanBaseHardware::diagnostics() const {
  std::vector<std::pair<std::string, std::string>> out;
  if (!bus_) return {{"CAN bus", "not open"}};
  const BusStatus s = bus_->status();
  out.emplace_back("CAN bus", bus_->description());
  out.emplace_back("CAN bus state", s.bus_off ? "bus-off" : (s.error_passive ? "error passive" : "ok"));
  out.emplace_back("CAN bus-off events", std::to_string(bus_off_events_));
  out.emplace_back("CAN frames sent", std::to_string(s.frames_sent));
  out.emplace_back("CAN frames received", std::to_string(s.frames_received));
  out.emplace_back("CAN send failures", std::to_string(s.send_failures));
  out.emplace_back("CAN receive overruns", std::to_string(s.receive_overruns));
  out.emplace_back("CAN error frames", std::to_string(s.error_frames));
  out.emplace_back("CAN arbitration lost", std::to_string(s.arbitration_lost));
  out.emplace_back("CAN malformed frames rejected", std::to_string(malformedFrames() + s.malformed));
  out.emplace_back("CAN relay queue overflow", std::to_string(relay_overflow_));
  out.emplace_back("CAN polls at the read bound", std::to_string(read_bound_hits_));
  out.emplace_back("CAN frames past the read bound", std::to_string(frames_past_bound_));
  if (!s.last_error.empty()) out.emplace_back("CAN last error", s.last_error);
  std::string missing;
  for (const auto& m : not_answering_) missing += (missing.empty() ? "" : ", ") + m;
  out.emplace_back("devices not answering at start-up", missing.empty() ? "none" : missing);
  for (const auto& d : devices_) out.emplace_back(d->label(), d->operational() ? "operational" : "not operational");
  return out;
}

}  // namespace thorvald_can_devices
