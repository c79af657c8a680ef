#include "cotton_harvester/control/serial_port.h"

#include <cerrno>
#include <cstring>

#include <fcntl.h>
#include <poll.h>
#include <pty.h>
#include <termios.h>
#include <unistd.h>

namespace cotton_harvester {
namespace control {
namespace {

bool baudConstant(int baud, speed_t* speed) {
  switch (baud) {
    case 9600:
      *speed = B9600;
      return true;
    case 19200:
      *speed = B19200;
      return true;
    case 38400:
      *speed = B38400;
      return true;
    case 57600:
      *speed = B57600;
      return true;
    case 115200:
      *speed = B115200;
      return true;
    case 230400:
      *speed = B230400;
      return true;
    default:
      return false;
  }
}

std::string errnoText(const std::string& what) { return what + ": " + std::strerror(errno); }

}  // namespace

SerialPort::~SerialPort() { close(); }

bool SerialPort::open(const std::string& path, int baud) {
  close();
  path_ = path;
  speed_t speed;
  if (!baudConstant(baud, &speed)) {
    last_error_ = "baud " + std::to_string(baud) + " is not supported";
    return false;
  }
  fd_ = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (fd_ < 0) {
    last_error_ = errnoText("cannot open " + path);
    return false;
  }
  termios tio{};
  if (tcgetattr(fd_, &tio) != 0) {
    fail(errnoText("tcgetattr " + path));
    return false;
  }
  cfmakeraw(&tio);
  tio.c_cflag |= CLOCAL | CREAD;
  tio.c_cflag &= ~(CSTOPB | PARENB | CRTSCTS);
  tio.c_cc[VMIN] = 0;
  tio.c_cc[VTIME] = 0;
  cfsetispeed(&tio, speed);
  cfsetospeed(&tio, speed);
  if (tcsetattr(fd_, TCSANOW, &tio) != 0) {
    fail(errnoText("tcsetattr " + path));
    return false;
  }
  tcflush(fd_, TCIFLUSH);
  last_error_.clear();
  return true;
}

void SerialPort::close() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

void SerialPort::fail(const std::string& what) {
  last_error_ = what;
  close();
}

bool SerialPort::write(const std::uint8_t* data, std::size_t size) {
  if (fd_ < 0) {
    if (last_error_.empty()) last_error_ = "port is not open";
    return false;
  }
  std::size_t done = 0;
  while (done < size) {
    const ssize_t n = ::write(fd_, data + done, size - done);
    if (n > 0) {
      done += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && (errno == EAGAIN || errno == EINTR)) {
      pollfd pfd{fd_, POLLOUT, 0};
      const int ready = ::poll(&pfd, 1, 100);
      if (ready <= 0 || (pfd.revents & (POLLERR | POLLHUP | POLLNVAL))) {
        fail("write to " + path_ + ": device does not take data (vanished?)");
        return false;
      }
      continue;
    }
    fail(errnoText("write to " + path_));
    return false;
  }
  return true;
}

long SerialPort::read(std::uint8_t* buffer, std::size_t size, int timeout_ms) {
  if (fd_ < 0) {
    if (last_error_.empty()) last_error_ = "port is not open";
    return -1;
  }
  pollfd pfd{fd_, POLLIN, 0};
  const int ready = ::poll(&pfd, 1, timeout_ms);
  if (ready < 0) {
    if (errno == EINTR) return 0;
    fail(errnoText("poll " + path_));
    return -1;
  }
  if (ready == 0) return 0;
  if (!(pfd.revents & POLLIN) && (pfd.revents & (POLLERR | POLLHUP | POLLNVAL))) {
    fail("device " + path_ + " hung up");
    return -1;
  }
  const ssize_t n = ::read(fd_, buffer, size);
  if (n < 0) {
    if (errno == EAGAIN || errno == EINTR) return 0;
    fail(errnoText("read " + path_));
    return -1;
  }
  if (n == 0) {
    fail("device " + path_ + " hung up");
    return -1;
  }
  return n;
}

PseudoTerminal::~PseudoTerminal() { close(); }

bool PseudoTerminal::open(const std::string& link_path) {
  close();
  char name[256] = {0};
  if (openpty(&master_, &slave_, name, nullptr, nullptr) != 0) {
    last_error_ = errnoText("openpty");
    master_ = slave_ = -1;
    return false;
  }
  termios tio{};
  tcgetattr(slave_, &tio);
  cfmakeraw(&tio);
  tcsetattr(slave_, TCSANOW, &tio);
  const int flags = fcntl(master_, F_GETFL);
  fcntl(master_, F_SETFL, flags | O_NONBLOCK);
  fcntl(master_, F_SETFD, FD_CLOEXEC);
  fcntl(slave_, F_SETFD, FD_CLOEXEC);
  slave_name_ = name;
  link_path_ = link_path;
  ::unlink(link_path_.c_str());
  if (::symlink(slave_name_.c_str(), link_path_.c_str()) != 0) {
    last_error_ = errnoText("symlink " + link_path_ + " -> " + slave_name_);
    close();
    return false;
  }
  return true;
}

void PseudoTerminal::close() {
  if (!link_path_.empty()) ::unlink(link_path_.c_str());
  link_path_.clear();
  if (slave_ >= 0) ::close(slave_);
  if (master_ >= 0) ::close(master_);
  slave_ = master_ = -1;
}

long PseudoTerminal::read(std::uint8_t* buffer, std::size_t size) {
  if (master_ < 0) return -1;
  const ssize_t n = ::read(master_, buffer, size);
  if (n < 0 && (errno == EAGAIN || errno == EINTR)) return 0;
  return n;
}

void PseudoTerminal::write(const std::uint8_t* data, std::size_t size) {
  if (master_ < 0) return;
  const ssize_t n = ::write(master_, data, size);
  (void)n;  // a full buffer drops bytes, as a UART without a reader would
}

}  // namespace control
}  // namespace cotton_harvester
