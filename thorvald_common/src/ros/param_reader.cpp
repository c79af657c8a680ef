#include "thorvald_common/ros/param_reader.h"

#include "thorvald_common/edit_distance.h"
#include "thorvald_common/ros/bounded_param_read.h"

#include <ros/console.h>
#include <ros/master.h>
#include <ros/this_node.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

namespace thorvald_common {
namespace {

std::string formatNumber(double v) {
  std::ostringstream s;
  s << std::setprecision(10) << v;
  return s.str();
}

bool coveredBy(const std::string& name, const std::set<std::string>& read) {
  if (read.count(name)) return true;
  for (size_t pos = name.find('/'); pos != std::string::npos; pos = name.find('/', pos + 1)) {
    if (read.count(name.substr(0, pos))) return true;  // a whole sub-tree was read
  }
  return false;
}

}  // namespace

bool ParamRange::contains(double v) const {
  if (std::isnan(v)) return false;
  if (min_open ? !(v > min) : !(v >= min)) return false;
  if (max_open ? !(v < max) : !(v <= max)) return false;
  return true;
}

std::string ParamRange::text() const {
  const bool has_min = std::isfinite(min), has_max = std::isfinite(max);
  if (has_min && has_max) {
    return std::string(min_open ? "(" : "[") + formatNumber(min) + ", " + formatNumber(max) + (max_open ? ")" : "]");
  }
  if (has_min) return std::string(min_open ? "> " : ">= ") + formatNumber(min);
  if (has_max) return std::string(max_open ? "< " : "<= ") + formatNumber(max);
  return "any finite value";
}

std::string describeParamValue(const XmlRpc::XmlRpcValue& value) {
  XmlRpc::XmlRpcValue& v = const_cast<XmlRpc::XmlRpcValue&>(value);  // XmlRpcValue's casts are not const
  switch (v.getType()) {
    case XmlRpc::XmlRpcValue::TypeBoolean:
      return std::string("the boolean ") + (static_cast<bool>(v) ? "true" : "false");
    case XmlRpc::XmlRpcValue::TypeInt:
      return "the integer " + std::to_string(static_cast<int>(v));
    case XmlRpc::XmlRpcValue::TypeDouble:
      return "the number " + formatNumber(static_cast<double>(v));
    case XmlRpc::XmlRpcValue::TypeString:
      return "the string '" + static_cast<std::string>(v) + "'";
    case XmlRpc::XmlRpcValue::TypeArray:
      return "a list of " + std::to_string(v.size()) + " values";
    case XmlRpc::XmlRpcValue::TypeStruct:
      return "a map";
    default:
      return "a value of another type";
  }
}

bool NodeHandleParamSource::get(const std::string& name, XmlRpc::XmlRpcValue& value) const {
  // Bounded like the robot file's groups: a value that expands past the bounds (YAML aliases loaded with
  // `rosparam load`) is refused before it is parsed.
  try {
    return getParamBounded(nh_.resolveName(name), value, ParamReadBounds{});
  } catch (const ParamTooLarge& e) {
    throw ParamError(nh_.resolveName(name) + ": " + e.what());
  }
}

std::vector<std::string> NodeHandleParamSource::names() const {
  constexpr size_t kMaxNameListBytes = 8u << 20;
  std::vector<std::string> out;
  const auto all = getParamNamesBounded(kMaxNameListBytes);
  if (!all) {
    ROS_WARN("%s: the parameter server's name list is larger than %zu bytes; unread parameters are not checked",
             nh_.getNamespace().c_str(), kMaxNameListBytes);
    return out;
  }
  const std::string prefix = nh_.getNamespace() + "/";
  for (const auto& n : *all) {
    if (n.size() > prefix.size() && n.compare(0, prefix.size(), prefix) == 0) out.push_back(n.substr(prefix.size()));
  }
  return out;
}

ParamReader::ParamReader(const ros::NodeHandle& private_nh, std::string node)
    : ParamReader(std::make_unique<NodeHandleParamSource>(private_nh),
                  node.empty() ? ros::this_node::getName() : std::move(node)) {}

ParamReader::ParamReader(std::unique_ptr<ParamSource> source, std::string node)
    : source_(std::move(source)), node_(std::move(node)) {}

bool ParamReader::fetch(const std::string& name, XmlRpc::XmlRpcValue& value) {
  read_.insert(name);
  return source_->get(name, value);
}

void ParamReader::fail(const std::string& name, const XmlRpc::XmlRpcValue& found, const std::string& expected) const {
  throw ParamError(node_ + ": parameter ~" + name + ": found " + describeParamValue(found) + ", expected " + expected);
}

void ParamReader::record(const std::string& name, const std::string& value, bool set) {
  effective_.push_back(name + "=" + value + (set ? "" : " (default)"));
}

double ParamReader::number(const std::string& name, double fallback, const ParamRange& range, const std::string& unit) {
  const bool bounded = std::isfinite(range.min) || std::isfinite(range.max);
  const std::string expected =
      std::string("a number") + (bounded ? " in " + range.text() : "") + (unit.empty() ? "" : " [" + unit + "]");
  XmlRpc::XmlRpcValue v;
  if (!fetch(name, v)) {
    record(name, formatNumber(fallback), false);
    return fallback;
  }
  double value = 0.0;
  if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble) {
    value = static_cast<double>(v);
  } else if (v.getType() == XmlRpc::XmlRpcValue::TypeInt) {
    value = static_cast<int>(v);
  } else {
    fail(name, v, expected);
  }
  if (!std::isfinite(value) || !range.contains(value)) fail(name, v, expected);
  record(name, formatNumber(value), true);
  return value;
}

int ParamReader::integer(const std::string& name, int fallback, int min, int max) {
  const std::string expected = "an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "]";
  XmlRpc::XmlRpcValue v;
  if (!fetch(name, v)) {
    record(name, std::to_string(fallback), false);
    return fallback;
  }
  double value = 0.0;
  if (v.getType() == XmlRpc::XmlRpcValue::TypeInt) {
    value = static_cast<int>(v);
  } else if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble) {
    value = static_cast<double>(v);
    if (!std::isfinite(value) || value != std::round(value)) fail(name, v, expected);
  } else {
    fail(name, v, expected);
  }
  if (value < min || value > max) fail(name, v, expected);
  const int out = static_cast<int>(value);
  record(name, std::to_string(out), true);
  return out;
}

bool ParamReader::flag(const std::string& name, bool fallback) {
  XmlRpc::XmlRpcValue v;
  if (!fetch(name, v)) {
    record(name, fallback ? "true" : "false", false);
    return fallback;
  }
  if (v.getType() != XmlRpc::XmlRpcValue::TypeBoolean) fail(name, v, "true or false");
  const bool out = static_cast<bool>(v);
  record(name, out ? "true" : "false", true);
  return out;
}

std::string ParamReader::text(const std::string& name, const std::string& fallback) {
  XmlRpc::XmlRpcValue v;
  if (!fetch(name, v)) {
    record(name, "'" + fallback + "'", false);
    return fallback;
  }
  if (v.getType() != XmlRpc::XmlRpcValue::TypeString) fail(name, v, "a string");
  const std::string out = static_cast<std::string>(v);
  record(name, "'" + out + "'", true);
  return out;
}

std::string ParamReader::choice(const std::string& name, const std::string& fallback,
                                const std::vector<std::string>& allowed) {
  std::string expected = "one of";
  for (size_t i = 0; i < allowed.size(); ++i) expected += (i ? ", '" : " '") + allowed[i] + "'";
  XmlRpc::XmlRpcValue v;
  if (!fetch(name, v)) {
    record(name, fallback, false);
    return fallback;
  }
  if (v.getType() != XmlRpc::XmlRpcValue::TypeString) fail(name, v, expected);
  const std::string out = static_cast<std::string>(v);
  if (std::find(allowed.begin(), allowed.end(), out) == allowed.end()) fail(name, v, expected);
  record(name, out, true);
  return out;
}

namespace {

std::string sizeText(size_t min_size, size_t max_size) {
  const size_t unbounded = std::numeric_limits<size_t>::max();
  if (min_size == max_size) return " of exactly " + std::to_string(min_size) + " elements";
  if (max_size != unbounded && min_size > 0)
    return " of " + std::to_string(min_size) + " to " + std::to_string(max_size) + " elements";
  if (max_size != unbounded) return " of at most " + std::to_string(max_size) + " elements";
  if (min_size > 0) return " of at least " + std::to_string(min_size) + " elements";
  return "";
}

template <typename T, typename Format>
std::string listText(const std::vector<T>& values, Format format) {
  std::string out = "[";
  for (size_t i = 0; i < values.size(); ++i) out += (i ? ", " : "") + format(values[i]);
  return out + "]";
}

}  // namespace

bool ParamReader::fetchList(const std::string& name, XmlRpc::XmlRpcValue& v, size_t min_size, size_t max_size,
                            const std::string& expected) {
  if (!fetch(name, v)) return false;
  if (v.getType() != XmlRpc::XmlRpcValue::TypeArray) fail(name, v, expected);
  const size_t n = static_cast<size_t>(v.size());
  if (n < min_size || n > max_size) fail(name, v, expected);
  return true;
}

std::vector<double> ParamReader::numbers(const std::string& name, const std::vector<double>& fallback,
                                         const ParamRange& range, const std::string& unit, size_t min_size,
                                         size_t max_size) {
  const bool bounded = std::isfinite(range.min) || std::isfinite(range.max);
  const std::string each = std::string("a number") + (bounded ? " in " + range.text() : "");
  const std::string expected =
      "a list" + sizeText(min_size, max_size) + ", each " + each + (unit.empty() ? "" : " [" + unit + "]");
  XmlRpc::XmlRpcValue v;
  if (!fetchList(name, v, min_size, max_size, expected)) {
    record(name, listText(fallback, formatNumber), false);
    return fallback;
  }
  std::vector<double> out;
  for (int i = 0; i < v.size(); ++i) {
    const std::string element = name + "[" + std::to_string(i) + "]";
    double value = 0.0;
    if (v[i].getType() == XmlRpc::XmlRpcValue::TypeDouble) {
      value = static_cast<double>(v[i]);
    } else if (v[i].getType() == XmlRpc::XmlRpcValue::TypeInt) {
      value = static_cast<int>(v[i]);
    } else {
      fail(element, v[i], each);
    }
    if (!std::isfinite(value) || !range.contains(value)) fail(element, v[i], each);
    out.push_back(value);
  }
  record(name, listText(out, formatNumber), true);
  return out;
}

std::vector<bool> ParamReader::flags(const std::string& name, const std::vector<bool>& fallback, size_t min_size,
                                     size_t max_size) {
  const auto format = [](bool b) { return std::string(b ? "true" : "false"); };
  XmlRpc::XmlRpcValue v;
  if (!fetchList(name, v, min_size, max_size, "a list" + sizeText(min_size, max_size) + " of true/false")) {
    record(name, listText(fallback, format), false);
    return fallback;
  }
  std::vector<bool> out;
  for (int i = 0; i < v.size(); ++i) {
    if (v[i].getType() != XmlRpc::XmlRpcValue::TypeBoolean)
      fail(name + "[" + std::to_string(i) + "]", v[i], "true or false");
    out.push_back(static_cast<bool>(v[i]));
  }
  record(name, listText(out, format), true);
  return out;
}

std::vector<std::string> ParamReader::texts(const std::string& name, const std::vector<std::string>& fallback,
                                            size_t min_size, size_t max_size, bool unique) {
  const auto format = [](const std::string& t) { return "'" + t + "'"; };
  const std::string expected =
      std::string("a list") + sizeText(min_size, max_size) + " of " + (unique ? "distinct " : "") + "strings";
  XmlRpc::XmlRpcValue v;
  if (!fetchList(name, v, min_size, max_size, expected)) {
    record(name, listText(fallback, format), false);
    return fallback;
  }
  std::vector<std::string> out;
  for (int i = 0; i < v.size(); ++i) {
    const std::string element = name + "[" + std::to_string(i) + "]";
    if (v[i].getType() != XmlRpc::XmlRpcValue::TypeString) fail(element, v[i], "a string");
    const std::string t = static_cast<std::string>(v[i]);
    if (unique && std::find(out.begin(), out.end(), t) != out.end())
      fail(element, v[i], "a string not already in the list");
    out.push_back(t);
  }
  record(name, listText(out, format), true);
  return out;
}

bool ParamReader::raw(const std::string& name, XmlRpc::XmlRpcValue* value) {
  XmlRpc::XmlRpcValue v;
  if (!fetch(name, v)) {
    record(name, "(not set)", false);
    return false;
  }
  record(name, describeParamValue(v), true);
  *value = v;
  return true;
}

void ParamReader::reject(const std::string& name, const std::string& why) {
  XmlRpc::XmlRpcValue v;
  if (fetch(name, v)) throw ParamError(node_ + ": parameter ~" + name + " is not supported: " + why);
}

bool ParamReader::has(const std::string& name) {
  XmlRpc::XmlRpcValue v;
  return fetch(name, v);
}

void ParamReader::alsoRead(const std::string& name) { read_.insert(name); }

std::vector<std::string> ParamReader::unread() const {
  std::vector<std::string> out;
  for (const auto& name : source_->names()) {
    if (!coveredBy(name, read_)) out.push_back(name);
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::string> ParamReader::finish() {
  std::vector<std::string> warnings;
  for (const auto& name : unread()) {
    std::string nearest;
    size_t best = std::string::npos;
    for (const auto& known : read_) {
      const size_t d = editDistance(name, known);
      if (d < best) {
        best = d;
        nearest = known;
      }
    }
    std::string w = node_ + ": private parameter ~" + name + " is set but nothing in this node reads it";
    if (!nearest.empty() && best <= std::max<size_t>(2, nearest.size() / 4)) {
      w += "; did you mean ~" + nearest + "?";
    }
    warnings.push_back(w);
  }
  for (const auto& w : warnings) ROS_WARN_STREAM(w);
  ROS_INFO_STREAM(node_ << ": parameters: " << effectiveValues());
  return warnings;
}

std::string ParamReader::effectiveValues() const {
  std::string out;
  for (const auto& e : effective_) out += (out.empty() ? "" : ", ") + e;
  return out.empty() ? "none" : out;
}

}  // namespace thorvald_common
