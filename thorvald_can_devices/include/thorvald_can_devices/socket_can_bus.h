#pragma once

#include <string>

#include "thorvald_can_devices/can_bus.h"

namespace thorvald_can_devices {

/// A raw SocketCAN socket on a named interface (`can0`). Subscribes to all error frames and decodes them into
/// status(): bus-off makes the bus unusable (ok == false) until the controller reports a restart or data frames
/// arrive again. A send that finds the transmit queue full (ENOBUFS/EAGAIN) is retried a bounded number of times,
/// waiting for the socket to become writable, then counted and reported; it never throws. When the interface
/// goes down (ENETDOWN/ENODEV) the socket is reopened once a second until it is back.
///
/// Kernels without CAN support (like this workspace's build machine) refuse PF_CAN sockets with EAFNOSUPPORT:
/// the constructor then throws a CanBusError that says so and points to the virtual bus.
class SocketCanBus : public CanBus {
 public:
  /// Throws CanBusError naming the interface and the failing step.
  explicit SocketCanBus(const std::string& interface_name);
  ~SocketCanBus() override;
  SocketCanBus(const SocketCanBus&) = delete;
  SocketCanBus& operator=(const SocketCanBus&) = delete;

  bool send(const CanFrame& frame) override;
  bool receive(CanFrame* frame) override;
  bool waitReadable(double timeout_s) override;
  BusStatus status() const override { return status_; }
  std::string description() const override { return "socketcan:" + interface_; }

  /// Send attempts before a frame is given up when the queue stays full.
  static constexpr int kSendAttempts = 4;

 private:
  void open();
  void markDown(int error_number);
  void tryReopen();

  std::string interface_;
  int fd_ = -1;
  bool down_ = false;
  double next_reopen_s_ = 0.0;
  BusStatus status_;
};

/// The message a SocketCanBus gives when the kernel refuses CAN sockets (tested; also used in docs).
std::string socketCanUnsupportedMessage(const std::string& interface_name);

}  // namespace thorvald_can_devices
