#include "thorvald_teleop/joystick_device.h"

#include <fcntl.h>
#include <linux/joystick.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace thorvald_teleop {

JoystickDevice::~JoystickDevice() { close(); }

bool JoystickDevice::open(const std::string& path, std::string& error) {
  close();
  fd_ = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0) {
    error = "cannot open " + path + ": " + std::strerror(errno);
    return false;
  }
  unsigned char axes = 0;
  unsigned char buttons = 0;
  char name[128] = {};
  axis_count_ = ::ioctl(fd_, JSIOCGAXES, &axes) == 0 ? axes : 0;
  button_count_ = ::ioctl(fd_, JSIOCGBUTTONS, &buttons) == 0 ? buttons : 0;
  name_ = ::ioctl(fd_, JSIOCGNAME(sizeof(name) - 1), name) > 0 ? name : "";
  partial_.clear();
  return true;
}

void JoystickDevice::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  partial_.clear();
}

JoystickDevice::ReadResult JoystickDevice::read(int timeout_ms, std::vector<JsEvent>& events, std::string& error) {
  if (fd_ < 0) {
    error = "device not open";
    return ReadResult::kDisconnected;
  }
  pollfd pfd{fd_, POLLIN, 0};
  const int ready = ::poll(&pfd, 1, timeout_ms);
  if (ready < 0) {
    if (errno == EINTR) return ReadResult::kTimeout;
    error = std::string("poll failed: ") + std::strerror(errno);
    return ReadResult::kDisconnected;
  }
  if (ready == 0) return ReadResult::kTimeout;
  bool any = false;
  for (;;) {
    char buffer[64 * sizeof(JsEvent)];
    const ssize_t n = ::read(fd_, buffer, sizeof(buffer));
    if (n > 0) {
      partial_.insert(partial_.end(), buffer, buffer + n);
      std::size_t used = 0;
      for (; used + sizeof(JsEvent) <= partial_.size(); used += sizeof(JsEvent)) {
        JsEvent e;
        std::memcpy(&e, partial_.data() + used, sizeof(JsEvent));
        events.push_back(e);
        any = true;
      }
      partial_.erase(partial_.begin(), partial_.begin() + static_cast<std::ptrdiff_t>(used));
      continue;
    }
    if (n == 0) {
      error = "end of file (device closed)";
      return any ? ReadResult::kEvents : ReadResult::kDisconnected;
    }
    if (errno == EAGAIN || errno == EWOULDBLOCK) return any ? ReadResult::kEvents : ReadResult::kTimeout;
    if (errno == EINTR) continue;
    error = std::string("read failed: ") + std::strerror(errno);
    return ReadResult::kDisconnected;
  }
}

}  // namespace thorvald_teleop
