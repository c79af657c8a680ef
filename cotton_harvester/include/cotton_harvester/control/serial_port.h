#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace cotton_harvester {
namespace control {

/// A serial device (USB-serial adapter or pseudo-terminal) in raw 8N1 mode, owned RAII.
/// A device that vanishes (unplugged, or the simulator's pseudo-terminal closed) shows as a failed
/// read or write: the port closes itself and lastError() says why, so the caller can reopen it.
class SerialPort {
 public:
  SerialPort() = default;
  ~SerialPort();
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;

  /// Opens `path` at `baud` (9600, 19200, 38400, 57600, 115200, 230400); discards stale input.
  /// Returns false with lastError() set when the device cannot be opened or configured.
  bool open(const std::string& path, int baud);
  void close();
  bool isOpen() const { return fd_ >= 0; }

  /// Writes all bytes (waiting up to 100 ms for room). False when the device failed (port closed).
  bool write(const std::uint8_t* data, std::size_t size);
  /// Waits up to `timeout_ms` for input and reads what is there (at most `size` bytes).
  /// Returns the count (0 on timeout) or -1 when the device failed or hung up (port closed).
  long read(std::uint8_t* buffer, std::size_t size, int timeout_ms);

  const std::string& lastError() const { return last_error_; }
  const std::string& path() const { return path_; }

 private:
  void fail(const std::string& what);
  int fd_ = -1;
  std::string path_;
  std::string last_error_;
};

/// The controller side of a simulated serial device: a pseudo-terminal whose slave end is published
/// as a symlink at `link_path`, which the nodes open as if it were /dev/ttyUSB0.
class PseudoTerminal {
 public:
  PseudoTerminal() = default;
  ~PseudoTerminal();
  PseudoTerminal(const PseudoTerminal&) = delete;
  PseudoTerminal& operator=(const PseudoTerminal&) = delete;

  /// Creates the pseudo-terminal and the symlink (replacing an old symlink). False with lastError().
  bool open(const std::string& link_path);
  /// Closes both ends and removes the symlink: to a reader the device vanishes.
  void close();
  bool isOpen() const { return master_ >= 0; }

  /// Non-blocking read of what the host wrote; -1 on error.
  long read(std::uint8_t* buffer, std::size_t size);
  /// Non-blocking write towards the host; bytes that do not fit are dropped (like a UART).
  void write(const std::uint8_t* data, std::size_t size);

  const std::string& slaveName() const { return slave_name_; }
  const std::string& lastError() const { return last_error_; }

 private:
  int master_ = -1;
  int slave_ = -1;  ///< kept open so the master never sees a hang-up while no host is connected
  std::string slave_name_;
  std::string link_path_;
  std::string last_error_;
};

}  // namespace control
}  // namespace cotton_harvester
