#include "thorvald_can_devices/virtual_can_bus.h"

#include <dirent.h>
#include <errno.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cstdlib>
#include <cstring>

#include "thorvald_can_devices/bus_error.h"

namespace thorvald_can_devices {
namespace {

std::atomic<int> endpoint_counter{0};

bool validName(const std::string& name) {
  if (name.empty() || name.size() > 48 || name == "." || name == "..") return false;
  for (char c : name) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.')) return false;
  }
  return true;
}

void makeFolder(const std::string& path) {
  for (size_t pos = 1; pos <= path.size(); ++pos) {
    if (pos == path.size() || path[pos] == '/') {
      const std::string part = path.substr(0, pos);
      if (::mkdir(part.c_str(), 0777) != 0 && errno != EEXIST) {
        throw CanBusError("virtual CAN bus: cannot create folder '" + part + "': " + std::strerror(errno), errno);
      }
    }
  }
}

sockaddr_un addressOf(const std::string& path) {
  sockaddr_un a{};
  a.sun_family = AF_UNIX;
  std::strncpy(a.sun_path, path.c_str(), sizeof(a.sun_path) - 1);
  return a;
}

long long nowRealtimeNs() {
  timespec ts{};
  ::clock_gettime(CLOCK_REALTIME, &ts);
  return static_cast<long long>(ts.tv_sec) * 1000000000LL + ts.tv_nsec;
}

}  // namespace

void encodeRecord(const CanFrame& frame, unsigned char record[16]) {
  std::memset(record, 0, 16);
  std::memcpy(record, &frame.id, 4);
  record[4] = frame.length > 8 ? 8 : frame.length;
  std::memcpy(record + 8, frame.data.data(), 8);
}

bool decodeRecord(const unsigned char* record, size_t size, CanFrame* frame) {
  if (size != 16 || record[4] > 8) return false;
  std::memcpy(&frame->id, record, 4);
  frame->length = record[4];
  std::memcpy(frame->data.data(), record + 8, 8);
  return true;
}

std::string VirtualCanBus::busFolder(const std::string& name) {
  const char* root = std::getenv("THORVALD_VCAN_DIR");
  return std::string(root && *root ? root : "/tmp/thorvald_vcan") + "/" + name;
}

VirtualCanBus::VirtualCanBus(const std::string& name) : name_(name), folder_(busFolder(name)) {
  if (!validName(name)) {
    throw CanBusError("virtual CAN bus: bad bus name '" + name + "': use 1..48 of [A-Za-z0-9_.-]");
  }
  makeFolder(folder_);
  own_path_ = folder_ + "/" + std::to_string(::getpid()) + "-" + std::to_string(endpoint_counter++);
  if (own_path_.size() >= sizeof(sockaddr_un::sun_path)) {
    throw CanBusError("virtual CAN bus: endpoint path '" + own_path_ + "' is too long for a Unix socket");
  }
  listen_fd_ = ::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (listen_fd_ < 0) throw CanBusError(std::string("virtual CAN bus: socket(): ") + std::strerror(errno), errno);
  ::unlink(own_path_.c_str());
  const sockaddr_un a = addressOf(own_path_);
  if (::bind(listen_fd_, reinterpret_cast<const sockaddr*>(&a), sizeof(a)) != 0 || ::listen(listen_fd_, 128) != 0) {
    const int e = errno;
    ::close(listen_fd_);
    throw CanBusError("virtual CAN bus: cannot listen on '" + own_path_ + "': " + std::strerror(e), e);
  }
  refreshPeers(true);
}

VirtualCanBus::~VirtualCanBus() {
  for (const auto& p : out_) ::close(p.fd);
  for (int fd : in_) ::close(fd);
  if (listen_fd_ >= 0) ::close(listen_fd_);
  ::unlink(own_path_.c_str());
}

void VirtualCanBus::refreshPeers(bool force) {
  struct stat st {};
  if (::stat(folder_.c_str(), &st) != 0) return;
  const long long mtime = static_cast<long long>(st.st_mtim.tv_sec) * 1000000000LL + st.st_mtim.tv_nsec;
  // The folder's time stamp is coarse (a kernel tick): while it is recent, an endpoint created in the same tick
  // could hide behind an unchanged time, so keep listing until it is 100 ms old.
  if (!force && mtime == folder_mtime_ns_ && nowRealtimeNs() - mtime > 100000000LL) return;
  folder_mtime_ns_ = mtime;
  std::vector<std::string> listed;
  if (DIR* dir = ::opendir(folder_.c_str())) {
    while (dirent* e = ::readdir(dir)) {
      if (e->d_name[0] == '.') continue;
      const std::string path = folder_ + "/" + e->d_name;
      if (path != own_path_) listed.push_back(path);
    }
    ::closedir(dir);
  }
  // Drop connections to endpoints that are gone, connect to new ones.
  for (size_t i = 0; i < out_.size();) {
    if (std::find(listed.begin(), listed.end(), out_[i].path) == listed.end()) {
      ::close(out_[i].fd);
      out_.erase(out_.begin() + static_cast<long>(i));
    } else {
      ++i;
    }
  }
  for (const auto& path : listed) {
    bool known = false;
    for (const auto& p : out_) known = known || p.path == path;
    if (known) continue;
    const int fd = ::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd < 0) continue;
    const int buf = 1 << 20;
    ::setsockopt(fd, SOL_SOCKET, SO_SNDBUF, &buf, sizeof(buf));
    const sockaddr_un a = addressOf(path);
    if (::connect(fd, reinterpret_cast<const sockaddr*>(&a), sizeof(a)) == 0) {
      out_.push_back({path, fd});
      continue;
    }
    const int e = errno;
    ::close(fd);
    if (e == ECONNREFUSED) {
      ::unlink(path.c_str());  // left behind by a process that died
    } else if (e == EAGAIN) {
      folder_mtime_ns_ = -1;  // its backlog is full: try again on the next send
    }
  }
}

size_t VirtualCanBus::peerCount() {
  refreshPeers(true);
  return out_.size();
}

bool VirtualCanBus::send(const CanFrame& frame) {
  if (frame.length > 8) {
    ++status_.send_failures;
    status_.last_error = "frame length above 8 refused";
    return false;
  }
  refreshPeers(false);
  unsigned char record[16];
  encodeRecord(frame, record);
  for (size_t i = 0; i < out_.size();) {
    const ssize_t n = ::send(out_[i].fd, record, sizeof(record), MSG_DONTWAIT | MSG_NOSIGNAL);
    if (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != ENOBUFS) {
      ::close(out_[i].fd);  // that endpoint closed; a new one may reuse its file name: list the folder again
      out_.erase(out_.begin() + static_cast<long>(i));
      folder_mtime_ns_ = -1;
      continue;
    }
    if (n < 0) ++status_.receive_overruns;  // that receiver's queue is full: it loses the frame
    ++i;
  }
  ++status_.frames_sent;
  return true;
}

void VirtualCanBus::acceptPending() {
  while (true) {
    const int fd = ::accept4(listen_fd_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) return;
    in_.push_back(fd);
  }
}

bool VirtualCanBus::receive(CanFrame* frame) {
  acceptPending();
  unsigned char record[32];
  size_t idle = 0;
  while (!in_.empty() && idle < in_.size()) {
    if (next_in_ >= in_.size()) next_in_ = 0;
    const int fd = in_[next_in_];
    const ssize_t n = ::recv(fd, record, sizeof(record), MSG_DONTWAIT);
    if (n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK)) {
      ::close(fd);  // the sender closed its end
      in_.erase(in_.begin() + static_cast<long>(next_in_));
      idle = 0;
      continue;
    }
    if (n < 0) {
      ++next_in_;
      ++idle;
      continue;
    }
    idle = 0;
    ++next_in_;  // round robin over senders
    CanFrame f;
    if (!decodeRecord(record, static_cast<size_t>(n), &f)) {
      ++status_.malformed;
      continue;
    }
    if (f.isError()) {
      recordBusError(f, status_);
      continue;
    }
    ++status_.frames_received;
    *frame = f;
    return true;
  }
  return false;
}

bool VirtualCanBus::waitReadable(double timeout_s) {
  std::vector<pollfd> fds;
  fds.push_back({listen_fd_, POLLIN, 0});
  for (int fd : in_) fds.push_back({fd, POLLIN, 0});
  const int ms = timeout_s <= 0.0 ? 0 : static_cast<int>(timeout_s * 1000.0 + 0.999);
  return ::poll(fds.data(), fds.size(), ms) > 0;
}

}  // namespace thorvald_can_devices
