#pragma once

#include <string>

#include <ros/ros.h>

namespace greenhouse_rail_nav {

/// Reads optional private parameters into a struct's fields: an absent key keeps the default, a key of
/// the wrong type is an error that names the key (never a silent fallback). Collects the first error.
class ParamReader {
 public:
  explicit ParamReader(const ros::NodeHandle& nh) : nh_(nh) {}

  template <typename T>
  void read(const std::string& key, T* value, const char* expected) {
    if (!error_.empty() || !nh_.hasParam(key)) return;
    T read_value{};
    if (!nh_.getParam(key, read_value)) {
      error_ = "parameter '" + nh_.resolveName(key) + "' must be " + expected;
      return;
    }
    *value = read_value;
  }
  void read(const std::string& key, double* value) { read(key, value, "a number"); }
  void read(const std::string& key, int* value) { read(key, value, "an integer"); }
  void read(const std::string& key, std::string* value) { read(key, value, "a string"); }
  void read(const std::string& key, bool* value) { read(key, value, "true or false"); }
  /// Records a validation failure (the struct's own check).
  void fail(const std::string& message) {
    if (error_.empty() && !message.empty()) error_ = "in " + nh_.getNamespace() + ": " + message;
  }
  const std::string& error() const { return error_; }

 private:
  ros::NodeHandle nh_;
  std::string error_;
};

}  // namespace greenhouse_rail_nav
