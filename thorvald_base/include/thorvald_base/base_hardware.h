#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "thorvald_base/battery.h"
#include "thorvald_base/io_board.h"
#include "thorvald_base/motor_drive.h"
#include "thorvald_base/robot_config.h"

namespace thorvald_common {
class ParamReader;
}  // namespace thorvald_common

namespace thorvald_base {

/// One classic CAN frame, as relayed between the base's bus and users.
struct CanFrameData {
  uint32_t id = 0;     ///< 11-bit identifier
  uint8_t length = 0;  ///< 0..8
  std::array<uint8_t, 8> data{};
};

/// The hardware a real base runs on (paper §3.1 `base_handle`): a bus with the drive and battery devices of the
/// robot file. Implemented by a plugin (thorvald_can_devices) so this package needs no bus code; base_driver
/// loads it with `~simple_sim: false`.
class BaseHardware {
 public:
  virtual ~BaseHardware() = default;

  /// Reads the plugin's own private parameters of base_driver (e.g. `~can_log`) through the node's reader, before
  /// initialize(); a bad value throws ParamError or ConfigError. Optional: the default reads none.
  virtual void readParameters(thorvald_common::ParamReader& params) { (void)params; }

  /// Opens the bus (`socketcan` or `virtual`, with its name) and creates one device per drive and battery.
  /// Throws std::runtime_error saying what could not be opened or created.
  virtual void initialize(const RobotConfig& config, const std::string& interface_type,
                          const std::string& interface_name) = 0;
  /// Hands over the drive devices, in drive index order. Called once after initialize.
  virtual std::vector<std::unique_ptr<MotorDrive>> takeDrives() = 0;
  /// Hands over the battery devices. Called once after initialize.
  virtual std::vector<std::unique_ptr<Battery>> takeBatteries() = 0;
  /// Hands over the relay boards (`io`). Called once after initialize. Optional: the default has none.
  virtual std::vector<std::unique_ptr<IoBoard>> takeIoBoards() { return {}; }
  /// Reads the bus; called every cycle before the devices are updated.
  virtual void poll(double now_s) = 0;
  /// Frames whose ids no base device owns, received since the last call.
  virtual std::vector<CanFrameData> takeRelayFrames() = 0;
  /// Sends a user's frame. Refuses (false, with why) ids of base devices, NMT and SYNC, and malformed frames.
  virtual bool sendRelayFrame(const CanFrameData& frame, std::string* why) = 0;
  /// Bus state for diagnostics: key/value pairs, and whether the bus is usable.
  virtual std::vector<std::pair<std::string, std::string>> diagnostics() const = 0;
  virtual bool busOk() const = 0;
  /// The base device or protocol that uses CAN id `id` ("drive1 (Thorvald controller, node 2)", "NMT", ...), ""
  /// when none does. The relay never carries such ids. Optional: the default knows none.
  virtual std::string canIdUser(uint32_t id) const {
    (void)id;
    return "";
  }
};

}  // namespace thorvald_base
