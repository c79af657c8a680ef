#include "thorvald_can_devices/virtual_can_bus.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <linux/sockios.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cstdio>
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

/// "<pid>-<n>": the only names this bus creates, connects to or removes.
bool endpointName(const char* name) {
  const char* p = name;
  if (!std::isdigit(static_cast<unsigned char>(*p))) return false;
  while (std::isdigit(static_cast<unsigned char>(*p))) ++p;
  if (*p++ != '-' || !std::isdigit(static_cast<unsigned char>(*p))) return false;
  while (std::isdigit(static_cast<unsigned char>(*p))) ++p;
  return *p == '\0';
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

[[noreturn]] void refuse(const std::string& path, const std::string& reason, int e = 0) {
  throw CanBusError("virtual CAN bus: refusing folder '" + path + "': " + reason, e);
}

}  // namespace

int openPrivateFolder(const std::string& path) {
  if (::mkdir(path.c_str(), 0700) != 0 && errno != EEXIST) {
    const int e = errno;
    refuse(path, std::string("cannot create it: ") + std::strerror(e), e);
  }
  const int fd = ::open(path.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) {
    const int e = errno;
    struct stat lst {};
    if (::lstat(path.c_str(), &lst) == 0 && S_ISLNK(lst.st_mode)) {
      refuse(path, "it is a symbolic link (remove it; the bus folder must be a real folder of this user)", e);
    }
    if (e == ENOTDIR) refuse(path, "it is not a folder", e);
    refuse(path, std::string("cannot open it: ") + std::strerror(e), e);
  }
  struct stat st {};
  std::string problem;
  if (::fstat(fd, &st) != 0) {
    problem = std::string("cannot stat it: ") + std::strerror(errno);
  } else if (!S_ISDIR(st.st_mode)) {
    problem = "it is not a folder";
  } else if (st.st_uid != ::geteuid()) {
    problem = "it belongs to uid " + std::to_string(st.st_uid) + ", not to this user (uid " +
              std::to_string(::geteuid()) + ")";
  } else if (st.st_mode & (S_IWGRP | S_IWOTH)) {
    char mode[8];
    std::snprintf(mode, sizeof(mode), "%04o", static_cast<unsigned>(st.st_mode & 07777));
    problem = std::string("its mode ") + mode + " lets group or others write (chmod 700 it)";
  }
  if (!problem.empty()) {
    ::close(fd);
    refuse(path, problem);
  }
  return fd;
}

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

std::string VirtualCanBus::rootFolder() {
  const char* root = std::getenv("THORVALD_VCAN_DIR");
  if (root && *root) return root;
  const char* runtime = std::getenv("XDG_RUNTIME_DIR");
  if (runtime && *runtime) return std::string(runtime) + "/thorvald_vcan";
  return "/tmp/thorvald_vcan-" + std::to_string(::geteuid());
}

std::string VirtualCanBus::busFolder(const std::string& name) { return rootFolder() + "/" + name; }

VirtualBusOptions VirtualCanBus::defaultOptions() {
  VirtualBusOptions o;
  const char* cap = std::getenv("THORVALD_VCAN_MAX_ENDPOINTS");
  if (cap && *cap) {
    char* end = nullptr;
    const long v = std::strtol(cap, &end, 10);
    if (*end != '\0' || v < 2 || v > 4096) {
      throw CanBusError(std::string("virtual CAN bus: THORVALD_VCAN_MAX_ENDPOINTS='") + cap +
                        "' must be an integer in 2..4096");
    }
    o.max_endpoints = static_cast<size_t>(v);
  }
  return o;
}

VirtualCanBus::VirtualCanBus(const std::string& name, VirtualBusOptions options) : name_(name), options_(options) {
  if (!validName(name)) {
    throw CanBusError("virtual CAN bus: bad bus name '" + name + "': use 1..48 of [A-Za-z0-9_.-]");
  }
  if (options_.max_endpoints < 2) throw CanBusError("virtual CAN bus: max_endpoints must be at least 2");
  const std::string root = rootFolder();
  ::close(openPrivateFolder(root));
  folder_ = root + "/" + name;
  folder_fd_ = openPrivateFolder(folder_);
  const auto existing = listEndpoints();
  if (existing.size() >= options_.max_endpoints) {
    ::close(folder_fd_);
    throw CanBusError("virtual CAN bus: bus '" + name + "' in '" + folder_ + "' already has " +
                      std::to_string(existing.size()) + " endpoints, the limit (THORVALD_VCAN_MAX_ENDPOINTS) is " +
                      std::to_string(options_.max_endpoints));
  }
  own_path_ = folder_ + "/" + std::to_string(::getpid()) + "-" + std::to_string(endpoint_counter++);
  if (own_path_.size() >= sizeof(sockaddr_un::sun_path)) {
    ::close(folder_fd_);
    throw CanBusError("virtual CAN bus: endpoint path '" + own_path_ + "' is too long for a Unix socket");
  }
  listen_fd_ = ::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (listen_fd_ < 0) {
    const int e = errno;
    ::close(folder_fd_);
    throw CanBusError(std::string("virtual CAN bus: socket(): ") + std::strerror(e), e);
  }
  const sockaddr_un a = addressOf(own_path_);
  // The name is this process's own (pid + counter); a leftover of an earlier process with the same pid is one of
  // our endpoint sockets: remove only that.
  struct stat st {};
  const std::string own_name = own_path_.substr(folder_.size() + 1);
  if (::fstatat(folder_fd_, own_name.c_str(), &st, AT_SYMLINK_NOFOLLOW) == 0 && S_ISSOCK(st.st_mode) &&
      st.st_uid == ::geteuid()) {
    ::unlinkat(folder_fd_, own_name.c_str(), 0);
  }
  if (::bind(listen_fd_, reinterpret_cast<const sockaddr*>(&a), sizeof(a)) != 0 || ::listen(listen_fd_, 128) != 0) {
    const int e = errno;
    ::close(listen_fd_);
    ::close(folder_fd_);
    throw CanBusError("virtual CAN bus: cannot listen on '" + own_path_ + "': " + std::strerror(e), e);
  }
  refreshPeers(true);
}

VirtualCanBus::~VirtualCanBus() {
  for (const auto& p : out_) ::close(p.fd);
  for (int fd : in_) ::close(fd);
  if (listen_fd_ >= 0) ::close(listen_fd_);
  ::unlinkat(folder_fd_, own_path_.substr(folder_.size() + 1).c_str(), 0);
  ::close(folder_fd_);
  ::rmdir(folder_.c_str());  // only succeeds when this was the last endpoint
}

std::vector<std::string> VirtualCanBus::listEndpoints() const {
  std::vector<std::string> names;
  const int fd = ::openat(folder_fd_, ".", O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return names;
  DIR* dir = ::fdopendir(fd);
  if (!dir) {
    ::close(fd);
    return names;
  }
  while (dirent* e = ::readdir(dir)) {
    if (!endpointName(e->d_name)) continue;
    struct stat st {};
    if (::fstatat(folder_fd_, e->d_name, &st, AT_SYMLINK_NOFOLLOW) != 0) continue;
    if (!S_ISSOCK(st.st_mode) || st.st_uid != ::geteuid()) continue;
    names.emplace_back(e->d_name);
  }
  ::closedir(dir);
  return names;
}

bool VirtualCanBus::sameUser(int fd) {
  ucred cred{};
  socklen_t len = sizeof(cred);
  if (::getsockopt(fd, SOL_SOCKET, SO_PEERCRED, &cred, &len) == 0 && cred.uid == ::geteuid()) return true;
  ++foreign_refused_;
  status_.last_error = "refused a connection from uid " + std::to_string(cred.uid) + " (pid " +
                       std::to_string(cred.pid) + "): only uid " + std::to_string(::geteuid()) + " may use this bus";
  return false;
}

void VirtualCanBus::refreshPeers(bool force) {
  struct stat st {};
  if (::fstat(folder_fd_, &st) != 0) return;
  const long long mtime = static_cast<long long>(st.st_mtim.tv_sec) * 1000000000LL + st.st_mtim.tv_nsec;
  // The folder's time stamp is coarse (a kernel tick): while it is recent, an endpoint created in the same tick
  // could hide behind an unchanged time, so keep listing until it is 100 ms old.
  if (!force && mtime == folder_mtime_ns_ && nowRealtimeNs() - mtime > 100000000LL) return;
  folder_mtime_ns_ = mtime;
  const std::string own_name = own_path_.substr(folder_.size() + 1);
  std::vector<std::string> listed;
  for (const auto& n : listEndpoints()) {
    if (n != own_name) listed.push_back(folder_ + "/" + n);
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
    if (out_.size() + 1 >= options_.max_endpoints) {
      ++endpoints_refused_;
      status_.last_error =
          "bus has more than " + std::to_string(options_.max_endpoints) + " endpoints: not sending to '" + path + "'";
      continue;
    }
    const int fd = ::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd < 0) continue;
    const int buf = 1 << 20;
    ::setsockopt(fd, SOL_SOCKET, SO_SNDBUF, &buf, sizeof(buf));
    const sockaddr_un a = addressOf(path);
    if (::connect(fd, reinterpret_cast<const sockaddr*>(&a), sizeof(a)) == 0) {
      if (sameUser(fd)) {
        out_.push_back({path, fd});
      } else {
        ::close(fd);
      }
      continue;
    }
    const int e = errno;
    ::close(fd);
    if (e == ECONNREFUSED) {
      // Left behind by a process that died: listEndpoints() checked it is one of our endpoint sockets.
      ::unlinkat(folder_fd_, path.substr(folder_.size() + 1).c_str(), 0);
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
    if (!sameUser(fd)) {
      ::close(fd);
    } else if (in_.size() + 1 >= options_.max_endpoints) {
      ::close(fd);
      ++endpoints_refused_;
      status_.last_error =
          "refused a connection: the bus already has " + std::to_string(options_.max_endpoints) + " endpoints";
    } else {
      in_.push_back(fd);
    }
  }
}

bool VirtualCanBus::receive(CanFrame* frame) {
  // New connections are accepted every 32 calls and whenever nothing is waiting: one accept4() per frame would
  // double the cost of reading a busy bus.
  if (in_.empty() || ++calls_since_accept_ >= 32) {
    acceptPending();
    calls_since_accept_ = 0;
  }
  unsigned char record[32];
  size_t idle = 0;
  // Error and malformed records are consumed here; a bounded number per call, so that a storm of them cannot hold
  // the caller (the next call goes on).
  int skipped = 0;
  while (!in_.empty() && idle < in_.size() && skipped < kMaxSkippedPerReceive) {
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
      ++skipped;
      continue;
    }
    if (f.isError()) {
      recordBusError(f, status_);
      ++skipped;
      continue;
    }
    ++status_.frames_received;
    *frame = f;
    return true;
  }
  if (calls_since_accept_ > 0) {
    calls_since_accept_ = 0;
    const size_t before = in_.size();
    acceptPending();
    if (in_.size() > before) return receive(frame);  // a new sender: read it now
  }
  return false;
}

long VirtualCanBus::framesWaiting() const {
  long records = 0;
  for (int fd : in_) {
    int bytes = 0;
    if (::ioctl(fd, SIOCINQ, &bytes) == 0 && bytes > 0) records += bytes / 16;
  }
  return records;
}

bool VirtualCanBus::waitReadable(double timeout_s) {
  std::vector<pollfd> fds;
  fds.push_back({listen_fd_, POLLIN, 0});
  for (int fd : in_) fds.push_back({fd, POLLIN, 0});
  const int ms = timeout_s <= 0.0 ? 0 : static_cast<int>(timeout_s * 1000.0 + 0.999);
  return ::poll(fds.data(), fds.size(), ms) > 0;
}

}  // namespace thorvald_can_devices
