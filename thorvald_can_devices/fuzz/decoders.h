#pragma once

#include <cstddef>
#include <cstdint>

namespace thorvald_can_devices {

/// Fuzz entry points, one per decoder family. Each turns the input into a frame (bytes 0-1: id, little-endian,
/// byte 2: length, then data), decodes it, and checks that a decoded frame re-encodes to a frame that decodes
/// to the same encoding. Traps on a broken invariant; never reads out of bounds.
void fuzzThorvaldFrames(const uint8_t* data, size_t size);
void fuzzBatteryFrames(const uint8_t* data, size_t size);
void fuzzCanopenFrames(const uint8_t* data, size_t size);
/// Input is one text line of a candump log.
void fuzzCandumpLine(const uint8_t* data, size_t size);

}  // namespace thorvald_can_devices
