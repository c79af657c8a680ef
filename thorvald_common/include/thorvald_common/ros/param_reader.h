#pragma once

#include <ros/node_handle.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include <limits>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace thorvald_common {

/// A private parameter with the wrong type or an unacceptable value. The message names the node, the parameter,
/// what was found and what was expected; a node reports it and exits with code 1.
class ParamError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Accepted interval of a numeric parameter; either end may be open or absent (infinite).
struct ParamRange {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_open = false;  ///< min itself is refused
  bool max_open = false;  ///< max itself is refused

  static ParamRange any() { return {}; }
  /// [min, max]
  static ParamRange closed(double min, double max) { return {min, max, false, false}; }
  /// (min, max]
  static ParamRange aboveUpTo(double min, double max) { return {min, max, true, false}; }
  /// (min, inf)
  static ParamRange above(double min) { return {min, std::numeric_limits<double>::infinity(), true, false}; }
  /// [min, inf)
  static ParamRange atLeast(double min) { return {min, std::numeric_limits<double>::infinity(), false, false}; }

  bool contains(double v) const;
  /// E.g. "(0, 1000]" or ">= 0".
  std::string text() const;
};

/// Where parameter values come from: the parameter server in a node, a map in tests.
class ParamSource {
 public:
  virtual ~ParamSource() = default;
  /// Value of the private parameter `name` (relative, e.g. "rate" or "limits/vx"); false if it is not set.
  virtual bool get(const std::string& name, XmlRpc::XmlRpcValue& value) const = 0;
  /// Every private parameter that is set, relative names of the leaves ("limits/vx").
  virtual std::vector<std::string> names() const = 0;
};

/// The private parameters of one node under its private NodeHandle (~).
class NodeHandleParamSource : public ParamSource {
 public:
  explicit NodeHandleParamSource(const ros::NodeHandle& private_nh) : nh_(private_nh) {}
  bool get(const std::string& name, XmlRpc::XmlRpcValue& value) const override;
  std::vector<std::string> names() const override;

 private:
  ros::NodeHandle nh_;
};

/// Strict, typed reading of a node's private parameters, shared by every node of the workspace.
///
/// Each read names the parameter, its default and what it accepts; a value of the wrong type or outside the
/// accepted values throws ParamError (the node exits 1) instead of falling back on the default. finish() warns
/// about private parameters that were set but that no read asked for (a typo like `cmd_vel_timout`), and logs
/// one line with the effective value of every parameter. Reads are not thread-safe; use it while starting up.
class ParamReader {
 public:
  /// Reads the private parameters of `private_nh`; `node` names the node in messages (default: this node).
  explicit ParamReader(const ros::NodeHandle& private_nh, std::string node = "");
  /// Reads from any source (tests).
  ParamReader(std::unique_ptr<ParamSource> source, std::string node);

  /// A number (int or double on the server) within `range`. `unit` (e.g. "Hz", "s") goes into messages.
  double number(const std::string& name, double fallback, const ParamRange& range, const std::string& unit = "");
  /// An integer within [min, max]; a double with an integral value is accepted.
  int integer(const std::string& name, int fallback, int min = std::numeric_limits<int>::min(),
              int max = std::numeric_limits<int>::max());
  /// true or false; strings such as "maybe" or "yes" are refused.
  bool flag(const std::string& name, bool fallback);
  /// Any string.
  std::string text(const std::string& name, const std::string& fallback);
  /// One of `allowed`.
  std::string choice(const std::string& name, const std::string& fallback, const std::vector<std::string>& allowed);
  /// A list of numbers, each within `range`, with between `min_size` and `max_size` elements.
  std::vector<double> numbers(const std::string& name, const std::vector<double>& fallback, const ParamRange& range,
                              const std::string& unit = "", size_t min_size = 0,
                              size_t max_size = std::numeric_limits<size_t>::max());
  /// A list of true/false values with between `min_size` and `max_size` elements.
  std::vector<bool> flags(const std::string& name, const std::vector<bool>& fallback, size_t min_size = 0,
                          size_t max_size = std::numeric_limits<size_t>::max());
  /// A list of strings with between `min_size` and `max_size` elements; `unique` refuses a repeated entry.
  std::vector<std::string> texts(const std::string& name, const std::vector<std::string>& fallback, size_t min_size = 0,
                                 size_t max_size = std::numeric_limits<size_t>::max(), bool unique = false);
  /// The raw value of a structured parameter (a map or list a library parses itself); false if not set.
  bool raw(const std::string& name, XmlRpc::XmlRpcValue* value);
  /// A parameter this node does not support: throws ParamError naming `why` if it is set.
  void reject(const std::string& name, const std::string& why);
  /// True if the parameter is set (it is then counted as read, e.g. by a library reading it itself).
  bool has(const std::string& name);

  /// Declares parameters that a library of this node reads itself (e.g. diagnostic_updater's
  /// `diagnostic_period`), or a whole sub-tree ("limits" covers "limits/vx"), so they are not reported unread.
  void alsoRead(const std::string& name);

  /// Warnings for private parameters nobody read, with the nearest known name. Logs them and the effective
  /// values (one line each) through rosconsole and returns the warnings.
  std::vector<std::string> finish();

  /// The private parameters that are set but were not read, relative names.
  std::vector<std::string> unread() const;
  /// "name=value" of every read parameter, in reading order, "(default)" after the ones not set.
  std::string effectiveValues() const;
  const std::string& node() const { return node_; }

 private:
  /// Fetches `name`; false if not set. Records the read.
  bool fetch(const std::string& name, XmlRpc::XmlRpcValue& value);
  [[noreturn]] void fail(const std::string& name, const XmlRpc::XmlRpcValue& found, const std::string& expected) const;
  void record(const std::string& name, const std::string& value, bool set);
  /// Fetches a list parameter and checks its type and size; false if not set.
  bool fetchList(const std::string& name, XmlRpc::XmlRpcValue& value, size_t min_size, size_t max_size,
                 const std::string& expected);

  std::unique_ptr<ParamSource> source_;
  std::string node_;
  std::set<std::string> read_;
  std::vector<std::string> effective_;
};

/// Text of a parameter value for messages: "the string 'fast'", "the number 3", "a map", ...
std::string describeParamValue(const XmlRpc::XmlRpcValue& value);

}  // namespace thorvald_common
