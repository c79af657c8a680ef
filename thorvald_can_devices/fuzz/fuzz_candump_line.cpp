// libFuzzer target: fuzzCandumpLine (see decoders.h).
#include "decoders.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  thorvald_can_devices::fuzzCandumpLine(data, size);
  return 0;
}
