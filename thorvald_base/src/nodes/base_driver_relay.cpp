// base_driver's CAN relay parameters: the allow-list (robot file's implement_can_ids or ~relay_allowed_ids). The
// relay itself is CanRelay (the decisions) and CanRelayRos (the topics).
#include <cmath>

#include "base_driver_ros.h"

namespace thorvald_base {

RelayIdList BaseDriverRos::readRelayIds(ParamReader& params, const RobotConfig& config) {
  RelayIdList list{config.implement_can_ids, config.source, "implement_can_ids"};
  if (!params.has("relay_allowed_ids")) return list;
  // The parameter overrides the robot file's list (e.g. on a test bench); the same ids are refused.
  const std::vector<double> ids =
      params.numbers("relay_allowed_ids", {}, ParamRange::closed(1, kMaxCanStdId), "", 0, kMaxModulesPerGroup);
  list = {{}, "base_driver", "~relay_allowed_ids"};
  for (size_t i = 0; i < ids.size(); ++i) {
    if (ids[i] != std::floor(ids[i])) {
      throw ConfigError("base_driver", "~relay_allowed_ids[" + std::to_string(i) + "]",
                        "must be an integer CAN id, found " + std::to_string(ids[i]));
    }
    list.ids.push_back(static_cast<int>(ids[i]));
  }
  return list;
}

}  // namespace thorvald_base
