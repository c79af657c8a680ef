#pragma once

#include <string>

#include "thorvald_can_devices/can_bus.h"
#include "thorvald_can_devices/can_frame.h"

namespace thorvald_can_devices {

/// Error classes of a Linux CAN error frame (linux/can/error.h), id bits.
constexpr uint32_t kErrTxTimeout = 0x001;
constexpr uint32_t kErrLostArbitration = 0x002;
constexpr uint32_t kErrController = 0x004;
constexpr uint32_t kErrProtocol = 0x008;
constexpr uint32_t kErrTransceiver = 0x010;
constexpr uint32_t kErrNoAck = 0x020;
constexpr uint32_t kErrBusOff = 0x040;
constexpr uint32_t kErrBusError = 0x080;
constexpr uint32_t kErrRestarted = 0x100;
/// data[1] bits for kErrController.
constexpr uint8_t kCtrlRxOverflow = 0x01, kCtrlTxOverflow = 0x02, kCtrlRxWarning = 0x04, kCtrlTxWarning = 0x08,
                  kCtrlRxPassive = 0x10, kCtrlTxPassive = 0x20, kCtrlActive = 0x40;

/// What one error frame says.
struct BusErrorReport {
  bool valid = false;  ///< it was an error frame
  bool bus_off = false;
  bool restarted = false;  ///< the controller left bus-off
  bool error_passive = false;
  bool error_active = false;  ///< back to error-active
  bool lost_arbitration = false;
  int arbitration_bit = -1;  ///< bit where arbitration was lost, -1 unknown
  bool controller_problem = false;
  bool protocol_violation = false;
  std::string text;  ///< all of it in words, e.g. "bus-off; controller: rx passive"
};

/// Decodes a SocketCAN error frame. Not an error frame: valid == false.
BusErrorReport decodeBusError(const CanFrame& frame);

/// Counts an error frame received on a bus into its status (bus-off, error-passive, lost arbitration, text).
void recordBusError(const CanFrame& error_frame, BusStatus& status);

/// Builds the error frame a controller reports for bus-off, error-passive or restart (used by the simulator).
CanFrame makeBusOffFrame();
CanFrame makeRestartedFrame();
CanFrame makeErrorPassiveFrame();

}  // namespace thorvald_can_devices
