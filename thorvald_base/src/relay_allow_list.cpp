#include "thorvald_base/relay_allow_list.h"

#include <cstdio>

namespace thorvald_base {

std::set<uint32_t> relayAllowList(const RelayIdList& list, const BaseHardware& hardware) {
  validateImplementCanIds(list.ids, list.source, list.key);
  std::set<uint32_t> allowed;
  for (size_t i = 0; i < list.ids.size(); ++i) {
    const auto id = static_cast<uint32_t>(list.ids[i]);
    const std::string user = hardware.canIdUser(id);
    if (!user.empty()) {
      char hex[16];
      std::snprintf(hex, sizeof(hex), "0x%03X", id);
      throw ConfigError(
          list.source, list.key + "[" + std::to_string(i) + "]",
          std::string("CAN id ") + hex + " is used by the base (" + user + "): only implement ids may be relayed");
    }
    allowed.insert(id);
  }
  return allowed;
}

}  // namespace thorvald_base
