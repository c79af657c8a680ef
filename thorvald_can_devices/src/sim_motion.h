#pragma once
// Small pieces shared by the simulated devices.
#include <algorithm>
#include <optional>

#include "thorvald_can_devices/canopen_protocol.h"

namespace thorvald_can_devices {

/// Moves `value` towards `target` by at most `max_step`.
inline double approach(double value, double target, double max_step) {
  if (target > value) return std::min(target, value + max_step);
  return std::max(target, value - max_step);
}

/// Whether an NMT message addresses `node` (directly or all nodes).
inline bool forNode(const std::optional<NmtMessage>& m, int node) { return m && (m->node == 0 || m->node == node); }

}  // namespace thorvald_can_devices
