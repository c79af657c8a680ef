#pragma once

#include <string>
#include <vector>

#include "thorvald_can_devices/can_bus.h"

namespace thorvald_can_devices {

/// A CAN bus between any number of processes that needs no kernel module.
///
/// Design (a mesh of Unix SEQPACKET connections, no broker): every open endpoint listens on a Unix SEQPACKET socket
/// at `<root>/<bus name>/<pid>-<n>` (root = $THORVALD_VCAN_DIR or /tmp/thorvald_vcan). A sender connects once to
/// every other endpoint file in the bus folder (listing the folder again when its modification time changes) and
/// writes each frame as one 16-byte record to each connection: SEQPACKET keeps record boundaries, and a connected
/// pair is limited by the socket buffer, not by the tiny datagram queue limit (net.unix.max_dgram_qlen, 10 here).
/// Sends never block: a receiver whose queue is full loses the frame (counted as an overrun, as a CAN controller's
/// receive FIFO overflows). Endpoint files of dead processes are removed by the next sender that finds nobody
/// listening. Order is kept per sender; frames of different senders interleave as the receiver reads them.
class VirtualCanBus : public CanBus {
 public:
  /// Opens bus `name` ([A-Za-z0-9_.-], 1..48 characters). Throws CanBusError.
  explicit VirtualCanBus(const std::string& name);
  ~VirtualCanBus() override;
  VirtualCanBus(const VirtualCanBus&) = delete;
  VirtualCanBus& operator=(const VirtualCanBus&) = delete;

  bool send(const CanFrame& frame) override;
  bool receive(CanFrame* frame) override;
  bool waitReadable(double timeout_s) override;
  BusStatus status() const override { return status_; }
  std::string description() const override { return "virtual:" + name_; }

  /// Folder that holds the endpoints of bus `name`.
  static std::string busFolder(const std::string& name);
  /// Number of other endpoints this one currently sends to (after a folder scan).
  size_t peerCount();
  /// This endpoint's socket file.
  const std::string& endpointPath() const { return own_path_; }

 private:
  struct Peer {
    std::string path;
    int fd;
  };
  void refreshPeers(bool force);
  void acceptPending();

  std::string name_, folder_, own_path_;
  int listen_fd_ = -1;
  long long folder_mtime_ns_ = -1;
  std::vector<Peer> out_;
  std::vector<int> in_;
  size_t next_in_ = 0;
  BusStatus status_;
};

/// Encodes a frame as the 16-byte record the virtual bus carries (layout of Linux struct can_frame, host order).
void encodeRecord(const CanFrame& frame, unsigned char record[16]);
/// Decodes a record; false when `size` is not 16 or the length byte is above 8.
bool decodeRecord(const unsigned char* record, size_t size, CanFrame* frame);

}  // namespace thorvald_can_devices
