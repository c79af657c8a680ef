#pragma once

#include <cstdint>
#include <set>
#include <string>
#include <vector>

#include "thorvald_base/base_hardware.h"

namespace thorvald_base {

/// CAN ids that users may exchange through base_driver's relay, and where they were configured.
struct RelayIdList {
  std::vector<int> ids;  ///< 11-bit identifiers
  std::string source;    ///< the robot file or the node that gave them, for messages
  std::string key;       ///< `implement_can_ids` (robot file) or `~relay_allowed_ids` (parameter)
};

/// The relay's allow-list: the ids of `list`, each an 11-bit id (0x001..0x7FF) listed once and used by no device
/// of the base (`hardware.canIdUser`: drives, batteries, NMT, SYNC, the host heartbeat). Everything outside it is
/// refused at run time. Throws ConfigError naming the entry and, for a base id, the device that uses it.
std::set<uint32_t> relayAllowList(const RelayIdList& list, const BaseHardware& hardware);

}  // namespace thorvald_base
