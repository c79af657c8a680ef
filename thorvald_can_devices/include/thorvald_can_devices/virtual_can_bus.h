#pragma once

#include <string>
#include <vector>

#include "thorvald_can_devices/can_bus.h"

namespace thorvald_can_devices {

/// Limits of one virtual bus endpoint.
struct VirtualBusOptions {
  /// Endpoints one bus may hold (this one included). Opening more is refused, and so are connections beyond it
  /// (each endpoint pins socket buffers in the kernel). $THORVALD_VCAN_MAX_ENDPOINTS overrides the default.
  size_t max_endpoints = 64;
};

/// A CAN bus between any number of processes of one user that needs no kernel module.
///
/// Design (a mesh of Unix SEQPACKET connections, no broker): every open endpoint listens on a Unix SEQPACKET socket
/// at `<root>/<bus name>/<pid>-<n>`. The root is $THORVALD_VCAN_DIR when set, else $XDG_RUNTIME_DIR/thorvald_vcan,
/// else /tmp/thorvald_vcan-<uid>. A sender connects once to every other endpoint socket in the bus folder (listing
/// the folder again when its modification time changes) and writes each frame as one 16-byte record to each
/// connection: SEQPACKET keeps record boundaries, and a connected pair is limited by the socket buffer, not by the
/// tiny datagram queue limit (net.unix.max_dgram_qlen, 10 here). Sends never block: a receiver whose queue is full
/// loses the frame (counted as an overrun, as a CAN controller's receive FIFO overflows). Order is kept per sender;
/// frames of different senders interleave round robin as the receiver reads them, so one flooding sender cannot
/// starve the others.
///
/// Security: the root and the bus folder must be directories owned by the current user without group or other
/// write permission (created 0700); a symbolic link, another owner or such a mode is refused with the path and the
/// reason. Every connection's peer (SO_PEERCRED) must run as the same user, else it is closed and counted.
/// Only sockets named like an endpoint and owned by this user are ever connected to or removed (stale endpoints of
/// dead processes are removed by the next sender that finds nobody listening). The last endpoint to close removes
/// the empty bus folder.
class VirtualCanBus : public CanBus {
 public:
  /// Opens bus `name` ([A-Za-z0-9_.-], 1..48 characters). Throws CanBusError naming the path and the reason.
  explicit VirtualCanBus(const std::string& name, VirtualBusOptions options = defaultOptions());
  ~VirtualCanBus() override;
  VirtualCanBus(const VirtualCanBus&) = delete;
  VirtualCanBus& operator=(const VirtualCanBus&) = delete;

  bool send(const CanFrame& frame) override;
  bool receive(CanFrame* frame) override;
  bool waitReadable(double timeout_s) override;
  BusStatus status() const override { return status_; }
  std::string description() const override { return "virtual:" + name_; }
  /// Records queued on the accepted connections (SIOCINQ counts a SEQPACKET socket's queued bytes).
  long framesWaiting() const override;

  /// Folder that holds every bus of this user (see the class comment).
  static std::string rootFolder();
  /// Folder that holds the endpoints of bus `name`.
  static std::string busFolder(const std::string& name);
  /// Defaults, with $THORVALD_VCAN_MAX_ENDPOINTS applied. Throws CanBusError for a malformed value.
  static VirtualBusOptions defaultOptions();
  /// Number of other endpoints this one currently sends to (after a folder scan).
  size_t peerCount();
  /// This endpoint's socket file.
  const std::string& endpointPath() const { return own_path_; }
  /// Connections refused because the peer ran as another user.
  unsigned long foreignPeersRefused() const { return foreign_refused_; }
  /// Connections refused because the bus already had max_endpoints endpoints.
  unsigned long endpointsRefused() const { return endpoints_refused_; }

 private:
  struct Peer {
    std::string path;
    int fd;
  };
  void refreshPeers(bool force);
  void acceptPending();
  std::vector<std::string> listEndpoints() const;
  bool sameUser(int fd);

  std::string name_, folder_, own_path_;
  VirtualBusOptions options_;
  int folder_fd_ = -1;
  int listen_fd_ = -1;
  long long folder_mtime_ns_ = -1;
  std::vector<Peer> out_;
  std::vector<int> in_;
  size_t next_in_ = 0;
  int calls_since_accept_ = 0;
  BusStatus status_;
  unsigned long foreign_refused_ = 0, endpoints_refused_ = 0;
};

/// Checks (creating it 0700 when missing) that `path` is a directory owned by this user, not a symbolic link and
/// without group or other write permission; returns an O_DIRECTORY descriptor opened without following links.
/// Throws CanBusError naming the path and the reason.
int openPrivateFolder(const std::string& path);

/// Encodes a frame as the 16-byte record the virtual bus carries (layout of Linux struct can_frame, host order).
void encodeRecord(const CanFrame& frame, unsigned char record[16]);
/// Decodes a record; false when `size` is not 16 or the length byte is above 8.
bool decodeRecord(const unsigned char* record, size_t size, CanFrame* frame);

}  // namespace thorvald_can_devices
