#pragma once

// Parameter reading shared by the control nodes: a missing key takes its default, a present key of
// the wrong kind or out of range stops the node with the key and what was expected.

#include <cmath>
#include <stdexcept>
#include <string>

#include <ros/ros.h>

namespace cotton_harvester {
namespace control {

/// Thrown by the readers; main() reports it and exits non-zero.
class ParamError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

inline double readDouble(const ros::NodeHandle& nh, const std::string& key, double fallback) {
  double value = fallback;
  if (nh.hasParam(key) && !nh.getParam(key, value)) {
    int as_int = 0;
    if (!nh.getParam(key, as_int)) throw ParamError(nh.resolveName(key) + ": expected a number");
    value = as_int;
  }
  if (!std::isfinite(value)) throw ParamError(nh.resolveName(key) + ": expected a finite number");
  return value;
}

inline double readPositive(const ros::NodeHandle& nh, const std::string& key, double fallback) {
  const double value = readDouble(nh, key, fallback);
  if (!(value > 0.0)) throw ParamError(nh.resolveName(key) + ": expected > 0, got " + std::to_string(value));
  return value;
}

inline int readInt(const ros::NodeHandle& nh, const std::string& key, int fallback, int min_value) {
  int value = fallback;
  if (nh.hasParam(key) && !nh.getParam(key, value)) throw ParamError(nh.resolveName(key) + ": expected an integer");
  if (value < min_value) {
    throw ParamError(nh.resolveName(key) + ": expected >= " + std::to_string(min_value) + ", got " +
                     std::to_string(value));
  }
  return value;
}

inline std::string readString(const ros::NodeHandle& nh, const std::string& key, const std::string& fallback) {
  std::string value = fallback;
  if (nh.hasParam(key) && !nh.getParam(key, value)) throw ParamError(nh.resolveName(key) + ": expected a string");
  return value;
}

inline bool readBool(const ros::NodeHandle& nh, const std::string& key, bool fallback) {
  bool value = fallback;
  if (nh.hasParam(key) && !nh.getParam(key, value)) throw ParamError(nh.resolveName(key) + ": expected true/false");
  return value;
}

/// Throws with the node's namespace when a library check() found a problem.
inline void requireSound(const ros::NodeHandle& nh, const std::string& problem) {
  if (!problem.empty()) throw ParamError(nh.resolveName("") + ": " + problem);
}

}  // namespace control
}  // namespace cotton_harvester
