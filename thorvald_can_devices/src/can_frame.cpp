#include "thorvald_can_devices/can_frame.h"

#include <cmath>
#include <cstdio>

namespace thorvald_can_devices {

bool operator==(const CanFrame& a, const CanFrame& b) {
  if (a.id != b.id || a.length != b.length) return false;
  for (int i = 0; i < a.length && i < 8; ++i)
    if (a.data[i] != b.data[i]) return false;
  return true;
}

CanFrame makeFrame(uint32_t id, std::initializer_list<uint8_t> bytes) {
  CanFrame f;
  f.id = id;
  for (uint8_t b : bytes) {
    if (f.length >= 8) break;
    f.data[f.length++] = b;
  }
  return f;
}

void putU16(CanFrame& f, int offset, uint16_t value) {
  f.data[offset] = static_cast<uint8_t>(value & 0xFF);
  f.data[offset + 1] = static_cast<uint8_t>(value >> 8);
}
void putI16(CanFrame& f, int offset, int16_t value) { putU16(f, offset, static_cast<uint16_t>(value)); }
void putU32(CanFrame& f, int offset, uint32_t value) {
  for (int i = 0; i < 4; ++i) f.data[offset + i] = static_cast<uint8_t>((value >> (8 * i)) & 0xFF);
}
void putI32(CanFrame& f, int offset, int32_t value) { putU32(f, offset, static_cast<uint32_t>(value)); }
uint16_t getU16(const CanFrame& f, int offset) {
  return static_cast<uint16_t>(f.data[offset] | (static_cast<uint16_t>(f.data[offset + 1]) << 8));
}
int16_t getI16(const CanFrame& f, int offset) { return static_cast<int16_t>(getU16(f, offset)); }
uint32_t getU32(const CanFrame& f, int offset) {
  uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= static_cast<uint32_t>(f.data[offset + i]) << (8 * i);
  return v;
}
int32_t getI32(const CanFrame& f, int offset) { return static_cast<int32_t>(getU32(f, offset)); }

int32_t clampToI32(double value, int32_t lo, int32_t hi) {
  if (std::isnan(value)) return 0;
  const double r = std::round(value);
  if (r <= lo) return lo;
  if (r >= hi) return hi;
  return static_cast<int32_t>(r);
}

std::string toString(const CanFrame& f) {
  char buf[64];
  int n;
  if (f.isError() || f.isExtended()) {
    n = std::snprintf(buf, sizeof(buf), "%08X#",
                      f.id & (f.isError() ? (kCanErrorFlag | kCanErrorMask) : kCanErrorMask));
  } else {
    n = std::snprintf(buf, sizeof(buf), "%03X#", f.stdId());
  }
  std::string out(buf, n);
  if (f.isRemote()) return out + "R";
  for (int i = 0; i < f.length && i < 8; ++i) {
    std::snprintf(buf, sizeof(buf), "%02X", f.data[i]);
    out += buf;
  }
  return out;
}

}  // namespace thorvald_can_devices
