#pragma once

// Parameter reading shared by the control nodes, through the workspace's thorvald_common::ParamReader: a missing key
// takes its default, a present key of the wrong kind or out of range stops the node with the key and what was
// expected, and parameters nobody read are warned about when the node calls the reader's finish().

#include <string>

#include <ros/ros.h>
#include <thorvald_common/ros/param_reader.h>

namespace cotton_harvester {
namespace control {

using thorvald_common::ParamError;

/// A node's private parameters, optionally under a sub-namespace ("calibration/"). Copies share the reader.
class NodeParams {
 public:
  explicit NodeParams(thorvald_common::ParamReader& reader, std::string prefix = "")
      : reader_(&reader), prefix_(std::move(prefix)) {}
  /// The parameters under `ns` (e.g. "calibration").
  NodeParams sub(const std::string& ns) const { return NodeParams(*reader_, prefix_ + ns + "/"); }
  thorvald_common::ParamReader& reader() const { return *reader_; }
  std::string key(const std::string& name) const { return prefix_ + name; }

 private:
  thorvald_common::ParamReader* reader_;
  std::string prefix_;
};

inline double readDouble(const NodeParams& p, const std::string& key, double fallback) {
  return p.reader().number(p.key(key), fallback, thorvald_common::ParamRange::any());
}

inline double readPositive(const NodeParams& p, const std::string& key, double fallback) {
  return p.reader().number(p.key(key), fallback, thorvald_common::ParamRange::above(0.0));
}

inline int readInt(const NodeParams& p, const std::string& key, int fallback, int min_value) {
  return p.reader().integer(p.key(key), fallback, min_value);
}

inline std::string readString(const NodeParams& p, const std::string& key, const std::string& fallback) {
  return p.reader().text(p.key(key), fallback);
}

inline bool readBool(const NodeParams& p, const std::string& key, bool fallback) {
  return p.reader().flag(p.key(key), fallback);
}

/// Throws with the node's name when a library check() found a problem.
inline void requireSound(const NodeParams&, const std::string& problem) {
  if (!problem.empty()) throw ParamError(ros::this_node::getName() + ": " + problem);
}

}  // namespace control
}  // namespace cotton_harvester
