#pragma once

// Reading one module map of a robot file by a table of its keys: the scalar reader that accepts field-file
// numbers (strings, floats for integers) and the field tables robot_config.cpp declares per module type.
// Internal to thorvald_base's library.

#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <limits>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "thorvald_base/robot_config.h"

namespace thorvald_base {
namespace detail {

/// Reads one scalar as a number; field files write numbers as strings and integers as floats.
class ScalarReader {
 public:
  ScalarReader(const std::string& source, std::string where) : source_(source), where_(std::move(where)) {}

  double number(const YAML::Node& node, const std::string& key) const {
    if (!node.IsScalar()) throw ConfigError(source_, where_ + "." + key, "expected a number, found a map or list");
    const std::string text = trim(node.Scalar());
    char* end = nullptr;
    errno = 0;
    const double value = std::strtod(text.c_str(), &end);
    if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(value)) {
      throw ConfigError(source_, where_ + "." + key, "expected a finite number, found '" + node.Scalar() + "'");
    }
    return value;
  }

  int integer(const YAML::Node& node, const std::string& key) const {
    const double value = number(node, key);
    if (std::fabs(value - std::round(value)) > 1e-9 || std::fabs(value) > 1e9) {
      throw ConfigError(source_, where_ + "." + key, "expected an integer, found '" + node.Scalar() + "'");
    }
    return static_cast<int>(std::lround(value));
  }

  bool boolean(const YAML::Node& node, const std::string& key) const {
    if (node.IsScalar()) {
      const std::string t = trim(node.Scalar());
      if (t == "true" || t == "True" || t == "TRUE" || t == "1" || t == "1.0") return true;
      if (t == "false" || t == "False" || t == "FALSE" || t == "0" || t == "0.0") return false;
    }
    throw ConfigError(source_, where_ + "." + key, "expected true or false");
  }

  std::string text(const YAML::Node& node, const std::string& key) const {
    if (!node.IsScalar()) throw ConfigError(source_, where_ + "." + key, "expected a string");
    return trim(node.Scalar());
  }

  const std::string& where() const { return where_; }
  const std::string& source() const { return source_; }

 private:
  static std::string trim(const std::string& s) {
    const auto b = s.find_first_not_of(" \t\r\n");
    if (b == std::string::npos) return "";
    return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
  }
  const std::string& source_;
  std::string where_;
};

/// The physical range of a numeric key, closed at both ends; `unit` goes into messages and the reference.
struct Bounds {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  const char* unit = "";

  bool contains(double v) const { return v >= min && v <= max; }
  std::string text() const {
    std::ostringstream s;
    s << "[" << min << ", " << max << "]" << (*unit ? " " : "") << unit;
    return s.str();
  }
};

/// Throws a ConfigError naming the key when `value` lies outside `bounds`.
inline void checkBounds(double value, const Bounds& bounds, const std::string& source, const std::string& where) {
  if (bounds.contains(value)) return;
  std::ostringstream s;
  s << "is " << value << ", outside its physical range " << bounds.text();
  throw ConfigError(source, where, s.str());
}

/// One key of a module: how to read it into the struct T. Tables of these replace if/else chains.
template <typename T>
struct Field {
  std::vector<std::string> names;  ///< first is the canonical name, the rest aliases
  bool required;
  std::function<void(T&, const ScalarReader&, const YAML::Node&, const std::string&)> read;
  Bounds bounds{};                          ///< numeric keys: accepted values
  std::function<double(const T&)> value{};  ///< numeric keys: the value as read, to check it again later
};

template <typename T, typename M>
Field<T> numberField(std::vector<std::string> names, bool required, M T::*member, Bounds bounds = {}) {
  return {std::move(names), required,
          [member, bounds](T& t, const ScalarReader& r, const YAML::Node& n, const std::string& k) {
            t.*member = r.number(n, k);
            checkBounds(t.*member, bounds, r.source(), r.where() + "." + k);
          },
          bounds, [member](const T& t) { return static_cast<double>(t.*member); }};
}

template <typename T>
Field<T> intField(std::vector<std::string> names, bool required, int T::*member, Bounds bounds = {}) {
  return {std::move(names), required,
          [member, bounds](T& t, const ScalarReader& r, const YAML::Node& n, const std::string& k) {
            t.*member = r.integer(n, k);
            checkBounds(t.*member, bounds, r.source(), r.where() + "." + k);
          },
          bounds, [member](const T& t) { return static_cast<double>(t.*member); }};
}

template <typename T>
Field<T> textField(std::vector<std::string> names, bool required, std::string T::*member) {
  return {std::move(names), required, [member](T& t, const ScalarReader& r, const YAML::Node& n, const std::string& k) {
            t.*member = r.text(n, k);
          }};
}

/// Reads the keys of one module map by a field table; unknown keys become warnings.
template <typename T>
void readFields(T& out, const YAML::Node& module, const std::vector<Field<T>>& fields, const ScalarReader& reader,
                std::vector<std::string>& warnings,
                const std::function<bool(const T&, const Field<T>&)>& required = {}) {
  if (!module.IsMap()) throw ConfigError(reader.source(), reader.where(), "expected a map of keys");
  std::set<std::string> known;
  for (const auto& field : fields) {
    YAML::Node found;  // a handle, not a pointer: the map iterator's pairs are temporaries
    std::string found_name;
    for (const auto& name : field.names) {
      known.insert(name);
      for (const auto& kv : module) {
        if (kv.first.Scalar() != name) continue;
        if (!found_name.empty()) {
          throw ConfigError(reader.source(), reader.where() + "." + name,
                            "given twice (as '" + found_name + "' and '" + name + "')");
        }
        found = kv.second;
        found_name = name;
      }
    }
    if (!found_name.empty()) field.read(out, reader, found, found_name);
  }
  for (const auto& field : fields) {
    bool present = false;
    for (const auto& name : field.names) present = present || module[name].IsDefined();
    const bool needed = required ? required(out, field) : field.required;
    if (!present && needed) throw ConfigError(reader.source(), reader.where() + "." + field.names[0], "is required");
  }
  for (const auto& kv : module) {
    if (!known.count(kv.first.Scalar())) {
      warnings.push_back(reader.source() + ": " + reader.where() + "." + kv.first.Scalar() + ": unknown key, ignored");
    }
  }
}

/// The keys of a drive module (`motor_drives.driveN`) with their physical ranges: read at load time (robot_config.cpp)
/// and checked again for a run-time change (validateDrive).
const std::vector<Field<DriveConfig>>& driveFields();

}  // namespace detail
}  // namespace thorvald_base
