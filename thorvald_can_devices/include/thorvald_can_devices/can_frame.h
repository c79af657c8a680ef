#pragma once

#include <array>
#include <cstdint>
#include <string>

namespace thorvald_can_devices {

/// Flags in the upper bits of CanFrame::id, as Linux SocketCAN uses them.
constexpr uint32_t kCanErrorFlag = 0x20000000U;  ///< error frame (bus state, not a data frame)
constexpr uint32_t kCanRtrFlag = 0x40000000U;    ///< remote transmission request
constexpr uint32_t kCanEffFlag = 0x80000000U;    ///< 29-bit identifier
constexpr uint32_t kCanStdMask = 0x7FFU;         ///< 11-bit identifier
constexpr uint32_t kCanErrorMask = 0x1FFFFFFFU;  ///< error class bits of an error frame

/// One classic CAN frame. Same meaning of the fields as Linux `struct can_frame`.
struct CanFrame {
  uint32_t id = 0;     ///< identifier with the flags above
  uint8_t length = 0;  ///< data length 0..8
  std::array<uint8_t, 8> data{};

  bool isError() const { return (id & kCanErrorFlag) != 0; }
  bool isExtended() const { return (id & kCanEffFlag) != 0; }
  bool isRemote() const { return (id & kCanRtrFlag) != 0; }
  /// The 11-bit identifier of a standard data frame.
  uint32_t stdId() const { return id & kCanStdMask; }
};

bool operator==(const CanFrame& a, const CanFrame& b);
inline bool operator!=(const CanFrame& a, const CanFrame& b) { return !(a == b); }

/// Builds a standard data frame from an id and bytes.
CanFrame makeFrame(uint32_t id, std::initializer_list<uint8_t> bytes);

/// Little-endian field access (CANopen byte order). `offset` + size must be <= 8.
void putU16(CanFrame& f, int offset, uint16_t value);
void putI16(CanFrame& f, int offset, int16_t value);
void putU32(CanFrame& f, int offset, uint32_t value);
void putI32(CanFrame& f, int offset, int32_t value);
uint16_t getU16(const CanFrame& f, int offset);
int16_t getI16(const CanFrame& f, int offset);
uint32_t getU32(const CanFrame& f, int offset);
int32_t getI32(const CanFrame& f, int offset);

/// Rounds and clamps a real value into an integer field range.
int32_t clampToI32(double value, int32_t lo, int32_t hi);

/// "123#DEADBEEF" (can-utils notation; error frames "20000004#..." with 8 hex digits).
std::string toString(const CanFrame& f);

}  // namespace thorvald_can_devices
