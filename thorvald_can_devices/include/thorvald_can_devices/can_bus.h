#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>

#include "thorvald_can_devices/can_frame.h"

namespace thorvald_can_devices {

/// A bus that cannot be opened: says which interface and why.
class CanBusError : public std::runtime_error {
 public:
  CanBusError(const std::string& what, int error_number = 0) : std::runtime_error(what), errno_(error_number) {}
  /// errno of the failing system call (0 when none).
  int errorNumber() const { return errno_; }

 private:
  int errno_;
};

/// Health of a bus and its counters, for diagnostics.
struct BusStatus {
  bool ok = true;              ///< usable: open, not bus-off
  bool bus_off = false;        ///< the controller is bus-off (or the interface is down)
  bool error_passive = false;  ///< the controller reported error-passive
  unsigned long frames_sent = 0;
  unsigned long frames_received = 0;
  unsigned long send_failures = 0;     ///< frames given up after the retry bound (queue full, interface down)
  unsigned long receive_overruns = 0;  ///< frames lost because a receiver's queue was full
  unsigned long error_frames = 0;      ///< error frames received
  unsigned long malformed = 0;         ///< received records that were not a whole CAN frame
  unsigned long arbitration_lost = 0;
  std::string last_error;  ///< the last problem, in words ("" when none)
};

/// Error or malformed records one receive() call consumes at most before it returns false.
constexpr int kMaxSkippedPerReceive = 64;

/// A CAN bus as the devices use it: non-blocking send and receive of classic frames. A frame sent is not
/// received back by the same CanBus object, but by every other one on the bus (as a SocketCAN raw socket).
/// Error frames are decoded into status() and never returned by receive(). Not thread-safe: one thread uses it.
class CanBus {
 public:
  virtual ~CanBus() = default;
  /// Queues one frame. False (counted, reason in status().last_error) when it could not be sent.
  virtual bool send(const CanFrame& frame) = 0;
  /// Takes the next received data frame; false when none is waiting.
  virtual bool receive(CanFrame* frame) = 0;
  /// Blocks up to `timeout_s` [s] until a frame may be read; true when one may.
  virtual bool waitReadable(double timeout_s) = 0;
  virtual BusStatus status() const = 0;
  /// "virtual:<name>" or "socketcan:<name>".
  virtual std::string description() const = 0;
  /// Frames received and waiting to be read; -1 when the bus cannot tell.
  virtual long framesWaiting() const { return -1; }
};

/// Opens a bus by type (`socketcan` or `virtual`) and name. Throws CanBusError saying what failed.
std::unique_ptr<CanBus> openCanBus(const std::string& type, const std::string& name);

}  // namespace thorvald_can_devices
