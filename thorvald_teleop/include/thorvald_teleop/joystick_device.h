#pragma once

#include <string>
#include <vector>

#include "thorvald_teleop/joystick_state.h"

namespace thorvald_teleop {

/// A Linux joystick device (/dev/input/js*) opened non-blocking; owns the file descriptor. Anything that delivers
/// js_event structs works, a FIFO included (then the axis and button counts are unknown and read as 0).
class JoystickDevice {
 public:
  enum class ReadResult { kEvents, kTimeout, kDisconnected };

  JoystickDevice() = default;
  ~JoystickDevice();
  JoystickDevice(const JoystickDevice&) = delete;
  JoystickDevice& operator=(const JoystickDevice&) = delete;

  /// Opens `path`; on failure returns false and sets `error` to the reason (errno text).
  bool open(const std::string& path, std::string& error);
  void close();
  bool isOpen() const { return fd_ >= 0; }
  /// Axis and button counts the driver reports; 0 when it does not (e.g. a FIFO).
  std::size_t axisCount() const { return axis_count_; }
  std::size_t buttonCount() const { return button_count_; }
  /// Device name from the driver, or empty.
  const std::string& name() const { return name_; }

  /// Waits up to `timeout_ms` [ms] for events and appends every complete one to `events`. kDisconnected when the
  /// device went away (unplugged, read error, or a FIFO's writer closed); `error` then says why.
  ReadResult read(int timeout_ms, std::vector<JsEvent>& events, std::string& error);

 private:
  int fd_ = -1;
  std::size_t axis_count_ = 0;
  std::size_t button_count_ = 0;
  std::string name_;
  std::vector<char> partial_;  ///< bytes of an event split across reads
};

}  // namespace thorvald_teleop
