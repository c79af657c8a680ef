// libFuzzer target: fuzzThorvaldFrames (see decoders.h).
#include "decoders.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  thorvald_can_devices::fuzzThorvaldFrames(data, size);
  return 0;
}
