#include "thorvald_can_devices/socket_can_bus.h"

#include <errno.h>
#include <linux/can.h>
#include <linux/can/error.h>
#include <linux/can/raw.h>
#include <net/if.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <cstring>

#include "thorvald_can_devices/bus_error.h"

namespace thorvald_can_devices {
namespace {
double monotonicS() {
  timespec ts{};
  ::clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}
}  // namespace

std::string socketCanUnsupportedMessage(const std::string& interface_name) {
  return "socketcan: cannot open a CAN socket for '" + interface_name +
         "': this kernel refuses CAN sockets (EAFNOSUPPORT, address family not supported): load the 'can' and "
         "'can_raw' kernel modules on the robot, or set ~can_interface_type to 'virtual' for the virtual bus";
}

SocketCanBus::SocketCanBus(const std::string& interface_name) : interface_(interface_name) {
  if (interface_name.empty() || interface_name.size() >= IFNAMSIZ) {
    throw CanBusError("socketcan: bad interface name '" + interface_name + "'");
  }
  open();
}

SocketCanBus::~SocketCanBus() {
  if (fd_ >= 0) ::close(fd_);
}

void SocketCanBus::open() {
  const int fd = ::socket(PF_CAN, SOCK_RAW | SOCK_NONBLOCK | SOCK_CLOEXEC, CAN_RAW);
  if (fd < 0) {
    const int e = errno;
    if (e == EAFNOSUPPORT) throw CanBusError(socketCanUnsupportedMessage(interface_), e);
    throw CanBusError("socketcan: socket(PF_CAN) for '" + interface_ + "': " + std::strerror(e), e);
  }
  ifreq ifr{};
  std::strncpy(ifr.ifr_name, interface_.c_str(), IFNAMSIZ - 1);
  if (::ioctl(fd, SIOCGIFINDEX, &ifr) != 0) {
    const int e = errno;
    ::close(fd);
    throw CanBusError("socketcan: no interface '" + interface_ + "': " + std::strerror(e), e);
  }
  const can_err_mask_t mask = CAN_ERR_MASK;
  ::setsockopt(fd, SOL_CAN_RAW, CAN_RAW_ERR_FILTER, &mask, sizeof(mask));
  sockaddr_can addr{};
  addr.can_family = AF_CAN;
  addr.can_ifindex = ifr.ifr_ifindex;
  if (::bind(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0) {
    const int e = errno;
    ::close(fd);
    throw CanBusError("socketcan: cannot bind to '" + interface_ + "': " + std::strerror(e), e);
  }
  fd_ = fd;
}

void SocketCanBus::markDown(int error_number) {
  down_ = true;
  status_.ok = false;
  status_.bus_off = true;
  status_.last_error = "interface " + interface_ + " down: " + std::strerror(error_number);
}

void SocketCanBus::tryReopen() {
  const double now = monotonicS();
  if (now < next_reopen_s_) return;
  next_reopen_s_ = now + 1.0;
  const int old = fd_;
  try {
    fd_ = -1;
    open();
    if (old >= 0) ::close(old);
    down_ = false;
    status_.ok = true;
    status_.bus_off = false;
    status_.last_error = "interface " + interface_ + " back";
  } catch (const CanBusError&) {
    fd_ = old;
  }
}

bool SocketCanBus::send(const CanFrame& frame) {
  if (down_) tryReopen();
  can_frame f{};
  f.can_id = frame.id;
  f.can_dlc = frame.length > 8 ? 8 : frame.length;
  std::memcpy(f.data, frame.data.data(), 8);
  for (int attempt = 0; attempt < kSendAttempts; ++attempt) {
    const ssize_t n = ::write(fd_, &f, sizeof(f));
    if (n == static_cast<ssize_t>(sizeof(f))) {
      ++status_.frames_sent;
      return true;
    }
    const int e = n < 0 ? errno : EIO;
    if (e == ENOBUFS || e == EAGAIN) {
      pollfd p{fd_, POLLOUT, 0};
      ::poll(&p, 1, 1);  // let the controller drain its queue for up to 1 ms
      continue;
    }
    if (e == ENETDOWN || e == ENODEV) markDown(e);
    ++status_.send_failures;
    status_.last_error = "send " + toString(frame) + ": " + std::strerror(e);
    return false;
  }
  ++status_.send_failures;
  status_.last_error =
      "send " + toString(frame) + ": transmit queue full after " + std::to_string(kSendAttempts) + " attempts";
  return false;
}

bool SocketCanBus::receive(CanFrame* frame) {
  if (down_) tryReopen();
  // Error and malformed frames are consumed here; a bounded number per call, so that a storm of them cannot hold
  // the caller (the next call goes on).
  for (int skipped = 0; skipped < kMaxSkippedPerReceive; ++skipped) {
    can_frame f{};
    const ssize_t n = ::read(fd_, &f, sizeof(f));
    if (n < 0) {
      if (errno == ENETDOWN || errno == ENODEV) markDown(errno);
      return false;
    }
    if (n != static_cast<ssize_t>(sizeof(f)) || f.can_dlc > 8) {
      ++status_.malformed;
      continue;
    }
    CanFrame out;
    out.id = f.can_id;
    out.length = f.can_dlc;
    std::memcpy(out.data.data(), f.data, 8);
    if (out.isError()) {
      recordBusError(out, status_);
      continue;
    }
    if (status_.bus_off && !down_) {  // traffic again: the controller recovered (auto restart)
      status_.bus_off = false;
      status_.ok = true;
    }
    ++status_.frames_received;
    *frame = out;
    return true;
  }
  return false;
}

bool SocketCanBus::waitReadable(double timeout_s) {
  pollfd p{fd_, POLLIN, 0};
  const int ms = timeout_s <= 0.0 ? 0 : static_cast<int>(timeout_s * 1000.0 + 0.999);
  return ::poll(&p, 1, ms) > 0 && (p.revents & POLLIN);
}

}  // namespace thorvald_can_devices
