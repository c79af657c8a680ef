#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "thorvald_can_devices/can_bus.h"

namespace thorvald_can_devices {

/// One node (or axis) on the base's bus as the host sees it. CanBaseHardware routes every received frame whose
/// id the device listens to into handle(), and calls tick() once per cycle so the device can send, check its
/// timeouts and step its start-up. One thread calls everything. Times are seconds of one monotonic clock.
class CanDevice {
 public:
  virtual ~CanDevice() = default;
  /// "drive0 (node 1)", "bat0 (id 2)".
  virtual std::string label() const = 0;
  /// Ids of frames the device receives from the bus.
  virtual std::vector<uint32_t> receiveIds() const = 0;
  /// Ids the host sends to the device (refused on the relay).
  virtual std::vector<uint32_t> transmitIds() const = 0;
  /// Begins start-up (NMT start, configuration) at time now_s.
  virtual void start(double now_s) = 0;
  virtual void handle(const CanFrame& frame, double now_s) = 0;
  virtual void tick(double now_s) = 0;
  /// Started and answering.
  virtual bool operational() const = 0;
  /// Frames with this device's ids that were rejected (wrong length, unknown type byte, bad value).
  virtual unsigned long malformed() const = 0;
  /// Bus-off (or interface down): devices report a fault while it lasts.
  void setBusOff(bool bus_off) { bus_off_ = bus_off; }

 protected:
  bool bus_off_ = false;
};

/// Seconds without a heartbeat after which a node is lost (docs/can_protocols.md: 2 s).
constexpr double kHeartbeatTimeoutS = 2.0;

}  // namespace thorvald_can_devices
