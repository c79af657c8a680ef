#pragma once

#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "thorvald_base/base_hardware.h"
#include "thorvald_can_devices/can_bus.h"
#include "thorvald_can_devices/can_device.h"
#include "thorvald_can_devices/cia402_drive.h"

namespace thorvald_can_devices {

/// Options of the CAN base that the robot file does not hold.
struct CanBaseOptions {
  double startup_timeout_s = 3.0;   ///< initialize() waits this long for every device to reach operation [s]
  std::string log_path;             ///< candump -l log of all traffic; "" for none
  size_t relay_queue_limit = 1000;  ///< received frames kept for the relay between two takeRelayFrames()
  /// Frames read from the bus in one poll at most: a flood cannot stall the control cycle; the rest waits in the
  /// socket (and a flooding sender's own frames overflow there).
  size_t max_frames_per_poll = 400;
  /// A drive whose feedback (Thorvald TPDOs, CiA 402 answers to SYNC) stops for this long is lost [s].
  double feedback_timeout_s = 0.06;
};

/// SYNC (to which every CiA 402 axis answers with its PDOs) goes out once per poll, but never closer than this:
/// start-up polls each time a frame arrives, and a SYNC per arrival made every answer trigger the next SYNC [s].
constexpr double kMinSyncPeriodS = 0.005;

/// The base's CAN hardware (paper §3.1 `base_handle`): one bus, one device per drive controller (Thorvald or
/// CiA 402, by the drive's `protocol` key), per battery and per relay board (CiA 401); routes received frames to their
/// device and all others to the relay; refuses relay frames aimed at base devices, NMT and SYNC. Its devices run on its
/// own monotonic clock (the `now_s` of poll() is not used), so start-up waiting and later cycles share one time base.
/// A bus-off (or a down interface) makes every drive report a fault, which stops the base.
class CanBaseHardware : public thorvald_base::BaseHardware {
 public:
  using Clock = std::function<double()>;
  /// `clock` in seconds; default: steady clock. Tests pass their own.
  explicit CanBaseHardware(CanBaseOptions options = {}, Clock clock = {});
  ~CanBaseHardware() override;

  void initialize(const thorvald_base::RobotConfig& config, const std::string& interface_type,
                  const std::string& interface_name) override;
  /// Same with a bus already open (tests, benchmarks).
  void initializeOnBus(const thorvald_base::RobotConfig& config, std::unique_ptr<CanBus> bus);
  std::vector<std::unique_ptr<thorvald_base::MotorDrive>> takeDrives() override;
  std::vector<std::unique_ptr<thorvald_base::Battery>> takeBatteries() override;
  /// One CiA 401 relay board per `io.ioN` (node = its id).
  std::vector<std::unique_ptr<thorvald_base::IoBoard>> takeIoBoards() override;
  void poll(double now_s) override;
  std::vector<thorvald_base::CanFrameData> takeRelayFrames() override;
  bool sendRelayFrame(const thorvald_base::CanFrameData& frame, std::string* why) override;
  std::vector<std::pair<std::string, std::string>> diagnostics() const override;
  bool busOk() const override;
  std::string canIdUser(uint32_t id) const override;

  /// Devices that did not reach operation during initialize(), with what they reported.
  const std::vector<std::string>& notAnswering() const { return not_answering_; }
  /// Ids owned by base devices (both directions), NMT and SYNC included.
  const std::set<uint32_t>& ownedIds() const { return owned_ids_; }
  CanBus& bus() { return *bus_; }
  unsigned long malformedFrames() const;
  /// Polls that stopped reading at max_frames_per_poll with frames still waiting.
  unsigned long readBoundHits() const { return read_bound_hits_; }
  /// Frames left waiting by those polls, summed over them (read by a later poll or lost to the receive queue's
  /// overflow). Exact on the virtual bus; SocketCAN does not tell how many wait, so each such poll counts one.
  unsigned long framesPastReadBound() const { return frames_past_bound_; }

  CanBaseOptions& options() { return options_; }

 private:
  void addDevice(std::shared_ptr<CanDevice> device, const std::string& source);
  void own(uint32_t id, const std::string& user);
  void addIoBoards(const thorvald_base::RobotConfig& config);
  void readBus(double now_s);
  double now() const { return clock_(); }

  CanBaseOptions options_;
  Clock clock_;
  std::unique_ptr<CanBus> bus_;
  std::vector<std::shared_ptr<CanDevice>> devices_;
  std::map<uint32_t, CanDevice*> routes_;
  std::set<uint32_t> owned_ids_;
  std::map<uint32_t, std::string> id_users_;  ///< who uses each owned id, for messages
  std::vector<std::unique_ptr<thorvald_base::MotorDrive>> drives_;
  std::vector<std::unique_ptr<thorvald_base::Battery>> batteries_;
  std::vector<std::unique_ptr<thorvald_base::IoBoard>> io_boards_;
  std::deque<thorvald_base::CanFrameData> relay_;
  unsigned long relay_overflow_ = 0;
  bool has_cia402_ = false;
  double last_host_heartbeat_s_ = -1e9;
  double last_sync_s_ = -1e9;
  std::vector<std::string> not_answering_;
  bool was_bus_ok_ = true;
  unsigned long bus_off_events_ = 0;
  unsigned long read_bound_hits_ = 0;
  unsigned long frames_past_bound_ = 0;
  std::vector<Cia402Axis*> cia402_axes_;
};

}  // namespace thorvald_can_devices
