#include "thorvald_can_devices/cia401_protocol.h"

#include "thorvald_can_devices/canopen_protocol.h"

namespace thorvald_can_devices {
namespace {
bool isData(const CanFrame& f) { return !f.isError() && !f.isExtended() && !f.isRemote(); }
}  // namespace

CanFrame encodeIoOutputs(int node, uint8_t outputs) {
  return makeFrame(canopen_ids::kRpdo1 + static_cast<uint32_t>(node), {outputs});
}

std::optional<uint8_t> decodeIoOutputs(const CanFrame& f) {
  if (!isData(f) || f.length != 1) return std::nullopt;
  return f.data[0];
}

CanFrame encodeIoFeedback(int node, const IoFeedback& feedback) {
  return makeFrame(canopen_ids::kTpdo1 + static_cast<uint32_t>(node), {feedback.inputs, feedback.outputs});
}

std::optional<IoFeedback> decodeIoFeedback(const CanFrame& f) {
  if (!isData(f) || f.length != 2) return std::nullopt;
  return IoFeedback{f.data[0], f.data[1]};
}

const char* nmtStateName(uint8_t state) {
  switch (state) {
    case kHeartbeatBootUp:
      return "boot-up";
    case kHeartbeatStopped:
      return "stopped";
    case kHeartbeatOperational:
      return "operational";
    case kHeartbeatPreOperational:
      return "pre-operational";
    default:
      return "unknown state";
  }
}

}  // namespace thorvald_can_devices
