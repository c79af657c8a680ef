#include "thorvald_gnss/nmea_line_server.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace thorvald_gnss {
namespace {

void setNonBlocking(int fd) { fcntl(fd, F_SETFL, fcntl(fd, F_GETFL, 0) | O_NONBLOCK); }

}  // namespace

NmeaLineServer::NmeaLineServer(const std::string& address, int port, size_t max_clients, size_t max_backlog_bytes)
    : max_clients_(max_clients), max_backlog_bytes_(max_backlog_bytes) {
  const std::string where = address + ":" + std::to_string(port);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  if (port < 0 || port > 65535 || inet_pton(AF_INET, address.c_str(), &addr.sin_addr) != 1) {
    throw std::runtime_error("NMEA server: " + where + " is not an IPv4 address and port (e.g. 127.0.0.1:10110)");
  }
  listen_fd_ = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (listen_fd_ < 0) throw std::runtime_error("NMEA server: socket: " + std::string(std::strerror(errno)));
  const int yes = 1;
  setsockopt(listen_fd_, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
  if (bind(listen_fd_, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0 || listen(listen_fd_, 4) != 0) {
    const std::string why = std::strerror(errno);
    ::close(listen_fd_);
    throw std::runtime_error("NMEA server: cannot listen on " + where + ": " + why);
  }
  setNonBlocking(listen_fd_);
  socklen_t len = sizeof(addr);
  getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&addr), &len);
  port_ = ntohs(addr.sin_port);
}

NmeaLineServer::~NmeaLineServer() {
  for (Client& c : clients_) ::close(c.fd);
  if (listen_fd_ >= 0) ::close(listen_fd_);
}

void NmeaLineServer::poll() {
  while (true) {
    const int fd = accept4(listen_fd_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) break;  // EAGAIN: nobody waiting
    if (clients_.size() >= max_clients_) {
      ::close(fd);
      ++dropped_;
      continue;
    }
    clients_.push_back({fd, {}});
    ++accepted_;
  }
  for (size_t i = clients_.size(); i-- > 0;) {
    // A client that closed its end shows as readable with 0 bytes; what a client sends is ignored.
    char buffer[256];
    const ssize_t n = recv(clients_[i].fd, buffer, sizeof(buffer), MSG_DONTWAIT);
    if (n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK)) {
      drop(i);
      continue;
    }
    flush(clients_[i]);
    if (clients_[i].fd < 0) drop(i);
  }
}

void NmeaLineServer::send(const std::string& text) {
  for (Client& c : clients_) {
    if (c.pending.size() + text.size() > max_backlog_bytes_) {
      ::close(c.fd);  // not reading: dropped below rather than holding the sentences of minutes
      c.fd = -1;
      continue;
    }
    c.pending += text;
  }
  poll();
}

void NmeaLineServer::flush(Client& client) {
  while (client.fd >= 0 && !client.pending.empty()) {
    const ssize_t n = ::send(client.fd, client.pending.data(), client.pending.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n > 0) {
      client.pending.erase(0, static_cast<size_t>(n));
    } else if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) {
      return;
    } else {
      ::close(client.fd);
      client.fd = -1;
    }
  }
}

void NmeaLineServer::drop(size_t index) {
  if (clients_[index].fd >= 0) ::close(clients_[index].fd);
  clients_.erase(clients_.begin() + static_cast<long>(index));
  ++dropped_;
}

}  // namespace thorvald_gnss
