#pragma once

#include <cstdint>
#include <optional>

#include "thorvald_can_devices/can_frame.h"
#include "thorvald_can_devices/thorvald_drive_protocol.h"

namespace thorvald_can_devices {

/// CiA 401 generic I/O module (relay board) as the base uses it: eight digital outputs written through RPDO1
/// (object 0x6200:01), read back with the inputs through TPDO1 (0x6000:01 and the outputs' echo), heartbeat and NMT
/// of CiA 301. Layouts and timing: docs/can_protocols.md, "CiA 401 relay boards".
namespace cia401 {
constexpr uint16_t kReadInputs8 = 0x6000, kWriteOutputs8 = 0x6200, kErrorModeOutputs8 = 0x6206,
                   kErrorValueOutputs8 = 0x6207;
constexpr int kOutputs = 8;                ///< outputs of one board (one 8-bit group)
constexpr double kTpdoPeriodS = 0.1;       ///< the board's TPDO1 event timer (and on every change) [s]
constexpr double kHeartbeatPeriodS = 0.1;  ///< the board's producer heartbeat (0x1017) [s]
/// A board that receives no RPDO1 for this long drives its outputs to the error value (off) [s].
constexpr double kRpdoTimeoutS = 0.5;
}  // namespace cia401

/// RPDO1, host -> board (0x200 + node, 1 byte): the outputs, bit i = output i (1 = relay closed).
CanFrame encodeIoOutputs(int node, uint8_t outputs);
std::optional<uint8_t> decodeIoOutputs(const CanFrame& f);

/// TPDO1, board -> host (0x180 + node, 2 bytes): the digital inputs, then the outputs as the board drives them.
struct IoFeedback {
  uint8_t inputs = 0;
  uint8_t outputs = 0;
};
CanFrame encodeIoFeedback(int node, const IoFeedback& feedback);
std::optional<IoFeedback> decodeIoFeedback(const CanFrame& f);

/// The heartbeat (0x700 + node, 1 byte: the NMT state) is CiA 301's, shared with the drives: encodeHeartbeat,
/// decodeHeartbeat and the kHeartbeat* states of thorvald_drive_protocol.h.

/// "operational", "pre-operational", "stopped", "boot-up" or "state 0x.." for the heartbeat byte.
const char* nmtStateName(uint8_t state);

}  // namespace thorvald_can_devices
