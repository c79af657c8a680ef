#include "thorvald_base/ros/base_calculator_loader.h"

#include <algorithm>
#include <vector>

#include "thorvald_common/edit_distance.h"

namespace thorvald_base {

BaseCalculatorLoader::BaseCalculatorLoader() : loader_("thorvald_base", "thorvald_base::BaseCalculator") {}

void BaseCalculatorLoader::check(const RobotConfig& config) const {
  std::vector<std::string> known = const_cast<pluginlib::ClassLoader<BaseCalculator>&>(loader_).getDeclaredClasses();
  if (std::find(known.begin(), known.end(), config.base_calculator) != known.end()) return;
  // The nearest spelling first: a typing slip shows at a glance.
  std::stable_sort(known.begin(), known.end(), [&](const std::string& a, const std::string& b) {
    return thorvald_common::editDistance(config.base_calculator, a) <
           thorvald_common::editDistance(config.base_calculator, b);
  });
  std::string list;
  for (const auto& k : known) list += (list.empty() ? "" : ", ") + k;
  throw ConfigError(config.source, "base_calculator",
                    "'" + config.base_calculator + "' names no kinematics plugin; expected one of: " +
                        (list.empty() ? std::string("(none found: is thorvald_base on ROS_PACKAGE_PATH?)") : list));
}

std::unique_ptr<BaseCalculator> BaseCalculatorLoader::create(const RobotConfig& config) {
  check(config);
  try {
    return std::unique_ptr<BaseCalculator>(loader_.createUnmanagedInstance(config.base_calculator));
  } catch (const pluginlib::PluginlibException& e) {
    throw ConfigError(config.source, "base_calculator",
                      "cannot load kinematics plugin '" + config.base_calculator + "': " + e.what());
  }
}

}  // namespace thorvald_base
