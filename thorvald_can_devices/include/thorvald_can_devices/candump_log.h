#pragma once

#include <cstdio>
#include <memory>
#include <string>

#include "thorvald_can_devices/can_bus.h"

namespace thorvald_can_devices {

/// One line of a can-utils `candump -l` log: "(1700000000.123456) can0 123#DEADBEEF".
std::string formatCandumpLine(double time_s, const std::string& interface_name, const CanFrame& frame);
/// Parses such a line (as canplayer reads it). False for anything else (counted by the caller).
bool parseCandumpLine(const std::string& line, double* time_s, std::string* interface_name, CanFrame* frame);

/// Writes frames to a file in `candump -l` format, readable and replayable with can-utils
/// (`canplayer -I file`, `log2asc`). Flushes every line so that a crash loses nothing.
class CandumpLogger {
 public:
  /// Throws CanBusError when the file cannot be opened.
  CandumpLogger(const std::string& path, std::string interface_name);
  ~CandumpLogger();
  CandumpLogger(const CandumpLogger&) = delete;
  CandumpLogger& operator=(const CandumpLogger&) = delete;
  void write(const CanFrame& frame);
  unsigned long lines() const { return lines_; }

 private:
  std::FILE* file_ = nullptr;
  std::string interface_;
  unsigned long lines_ = 0;
};

/// A CanBus that logs every frame sent and received (and error frames are not seen: they are decoded below).
class LoggingCanBus : public CanBus {
 public:
  LoggingCanBus(std::unique_ptr<CanBus> inner, const std::string& path, const std::string& interface_name);
  bool send(const CanFrame& frame) override;
  bool receive(CanFrame* frame) override;
  bool waitReadable(double timeout_s) override { return inner_->waitReadable(timeout_s); }
  BusStatus status() const override { return inner_->status(); }
  std::string description() const override { return inner_->description(); }
  long framesWaiting() const override { return inner_->framesWaiting(); }

 private:
  std::unique_ptr<CanBus> inner_;
  CandumpLogger log_;
};

}  // namespace thorvald_can_devices
