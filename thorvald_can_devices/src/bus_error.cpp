#include "thorvald_can_devices/bus_error.h"

namespace thorvald_can_devices {
namespace {
void append(std::string& text, const std::string& part) { text += (text.empty() ? "" : "; ") + part; }
}  // namespace

BusErrorReport decodeBusError(const CanFrame& f) {
  BusErrorReport r;
  if (!f.isError()) return r;
  r.valid = true;
  const uint32_t cls = f.id & kCanErrorMask;
  const uint8_t ctrl = f.length > 1 ? f.data[1] : 0;
  if (cls & kErrTxTimeout) append(r.text, "transmit timeout");
  if (cls & kErrLostArbitration) {
    r.lost_arbitration = true;
    if (f.length > 0 && f.data[0] != 0) r.arbitration_bit = f.data[0];
    append(r.text, "lost arbitration" +
                       (r.arbitration_bit >= 0 ? " at bit " + std::to_string(r.arbitration_bit) : std::string()));
  }
  if (cls & kErrController) {
    r.controller_problem = true;
    std::string what;
    if (ctrl & kCtrlRxOverflow) append(what, "rx overflow");
    if (ctrl & kCtrlTxOverflow) append(what, "tx overflow");
    if (ctrl & kCtrlRxWarning) append(what, "rx warning");
    if (ctrl & kCtrlTxWarning) append(what, "tx warning");
    if (ctrl & (kCtrlRxPassive | kCtrlTxPassive)) {
      r.error_passive = true;
      append(what, "error passive");
    }
    if (ctrl & kCtrlActive) {
      r.error_active = true;
      append(what, "error active");
    }
    append(r.text, "controller: " + (what.empty() ? std::string("unspecified") : what));
  }
  if (cls & kErrProtocol) {
    r.protocol_violation = true;
    append(r.text, "protocol violation (type 0x" + std::to_string(f.length > 2 ? f.data[2] : 0) + ")");
  }
  if (cls & kErrTransceiver) append(r.text, "transceiver");
  if (cls & kErrNoAck) append(r.text, "no acknowledge");
  if (cls & kErrBusOff) {
    r.bus_off = true;
    append(r.text, "bus-off");
  }
  if (cls & kErrBusError) append(r.text, "bus error");
  if (cls & kErrRestarted) {
    r.restarted = true;
    append(r.text, "controller restarted");
  }
  if (r.text.empty()) r.text = "error frame without class";
  return r;
}

CanFrame makeBusOffFrame() {
  CanFrame f;
  f.id = kCanErrorFlag | kErrBusOff;
  f.length = 8;
  return f;
}
CanFrame makeRestartedFrame() {
  CanFrame f;
  f.id = kCanErrorFlag | kErrRestarted;
  f.length = 8;
  return f;
}
CanFrame makeErrorPassiveFrame() {
  CanFrame f;
  f.id = kCanErrorFlag | kErrController;
  f.length = 8;
  f.data[1] = kCtrlRxPassive | kCtrlTxPassive;
  return f;
}

void recordBusError(const CanFrame& error_frame, BusStatus& status) {
  ++status.error_frames;
  const BusErrorReport r = decodeBusError(error_frame);
  status.last_error = r.text;
  if (r.lost_arbitration) ++status.arbitration_lost;
  if (r.bus_off) status.bus_off = true;
  if (r.restarted) status.bus_off = false;
  if (r.error_passive) status.error_passive = true;
  if (r.error_active || r.restarted) status.error_passive = false;
  status.ok = !status.bus_off;
}

}  // namespace thorvald_can_devices
