#pragma once

#include <set>
#include <string>
#include <vector>

#include <ros/ros.h>

namespace thorvald_navigation {

/// Reads optional private parameters into a component's fields: an absent key keeps the default, a key of the
/// wrong type is an error that names the full parameter (never a silent fallback); remembers the keys it read so
/// that unread ones (typos) can be warned about. The first error is kept.
class ParamReader {
 public:
  explicit ParamReader(const ros::NodeHandle& pnh) : nh_(pnh) {}

  template <typename T>
  void read(const std::string& key, T* value, const char* expected) {
    read_.insert(key);
    if (!error_.empty() || !nh_.hasParam(key)) return;
    T v{};
    if (!nh_.getParam(key, v)) {
      error_ = "parameter '" + nh_.resolveName(key) + "' must be " + expected;
      return;
    }
    *value = v;
  }
  void read(const std::string& key, double* value) { read(key, value, "a number"); }
  void read(const std::string& key, int* value) { read(key, value, "an integer"); }
  void read(const std::string& key, bool* value) { read(key, value, "true or false"); }
  void read(const std::string& key, std::string* value) { read(key, value, "a string"); }
  void read(const std::string& key, std::vector<double>* value) { read(key, value, "a list of numbers"); }
  void read(const std::string& key, std::vector<bool>* value) { read(key, value, "a list of true/false"); }
  /// A key that must not be set because the node does not support what it asks for.
  void reject(const std::string& key, const std::string& why) {
    read_.insert(key);
    if (error_.empty() && nh_.hasParam(key))
      error_ = "parameter '" + nh_.resolveName(key) + "' is not supported: " + why;
  }
  /// A key accepted for compatibility that has no effect here.
  void ignore(const std::string& key) { read_.insert(key); }
  /// Records a validation failure of the component's own check.
  void fail(const std::string& message) {
    if (error_.empty() && !message.empty()) error_ = "in " + nh_.getNamespace() + ": " + message;
  }
  /// Private parameters that exist but were never read (typos, unsupported options).
  std::vector<std::string> unread() const {
    std::vector<std::string> names, out;
    nh_.getParamNames(names);
    const std::string prefix = nh_.getNamespace() + "/";
    for (const auto& n : names) {
      if (n.compare(0, prefix.size(), prefix) != 0) continue;
      const std::string key = n.substr(prefix.size());
      const std::string top = key.substr(0, key.find('/'));
      if (!read_.count(top)) out.push_back(key);
    }
    return out;
  }
  void warnUnread(const char* node) const {
    for (const auto& k : unread()) ROS_WARN_STREAM(node << ": parameter ~" << k << " is not used by this node");
  }
  const std::string& error() const { return error_; }

 private:
  ros::NodeHandle nh_;
  std::set<std::string> read_;
  std::string error_;
};

}  // namespace thorvald_navigation
