#pragma once

// A TCP server that hands NMEA sentences to whoever connects (gpsd reading `tcp://host:port`, or `nc` for a look):
// what a receiver's "TCP server" NMEA output does. Non-blocking and bounded: a client that does not read is
// dropped once its backlog passes a limit. ROS-free (POSIX sockets).

#include <cstddef>
#include <string>
#include <vector>

namespace thorvald_gnss {

class NmeaLineServer {
 public:
  /// Listens on `address`:`port` (port 0: any free port, see port()). Throws std::runtime_error naming the address
  /// and the system's reason when it cannot.
  NmeaLineServer(const std::string& address, int port, size_t max_clients = 8, size_t max_backlog_bytes = 65536);
  ~NmeaLineServer();
  NmeaLineServer(const NmeaLineServer&) = delete;
  NmeaLineServer& operator=(const NmeaLineServer&) = delete;

  /// The port it listens on.
  int port() const { return port_; }
  /// Accepts waiting clients and sends what is pending; call it often (each publish calls it too).
  void poll();
  /// Sends `text` (whole sentences with their CR LF) to every client.
  void send(const std::string& text);
  size_t clients() const { return clients_.size(); }
  unsigned long accepted() const { return accepted_; }
  unsigned long dropped() const { return dropped_; }

 private:
  struct Client {
    int fd = -1;
    std::string pending;
  };
  void flush(Client& client);
  void drop(size_t index);

  int listen_fd_ = -1;
  int port_ = 0;
  size_t max_clients_;
  size_t max_backlog_bytes_;
  std::vector<Client> clients_;
  unsigned long accepted_ = 0;
  unsigned long dropped_ = 0;
};

}  // namespace thorvald_gnss
