#include "thorvald_twist_mux/mux_config.h"

#include <cmath>
#include <set>
#include <sstream>

namespace thorvald_twist_mux {
namespace {

std::string validateList(const std::vector<MuxEntry>& entries, const std::string& list_name) {
  std::set<std::string> names;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const MuxEntry& e = entries[i];
    std::ostringstream where;
    where << list_name << "[" << i << "] (" << e.name << "): ";
    if (e.name.empty()) return where.str() + "name is empty, expected a non-empty string";
    if (e.topic.empty()) return where.str() + "topic is empty, expected a topic name";
    if (!std::isfinite(e.timeout_s) || e.timeout_s < 0.0) {
      std::ostringstream msg;
      msg << where.str() << "timeout is " << e.timeout_s << ", expected a finite number >= 0 (0 = never expires)";
      return msg.str();
    }
    if (e.priority < 0 || e.priority > 255) {
      std::ostringstream msg;
      msg << where.str() << "priority is " << e.priority << ", expected an integer in 0..255";
      return msg.str();
    }
    if (!names.insert(e.name).second) return where.str() + "duplicate name, expected each name once in " + list_name;
  }
  return {};
}

}  // namespace

std::string validateMuxConfig(const MuxConfig& config) {
  if (config.inputs.empty()) return "topics: no inputs, expected at least one {name, topic, timeout, priority}";
  std::string error = validateList(config.inputs, "topics");
  if (!error.empty()) return error;
  return validateList(config.locks, "locks");
}

}  // namespace thorvald_twist_mux
