#include "mux_params.h"

#include <cmath>
#include <stdexcept>

namespace thorvald_twist_mux {
namespace {

using XmlRpc::XmlRpcValue;

std::string typeName(XmlRpcValue::Type type) {
  switch (type) {
    case XmlRpcValue::TypeBoolean:
      return "a bool";
    case XmlRpcValue::TypeInt:
      return "an int";
    case XmlRpcValue::TypeDouble:
      return "a double";
    case XmlRpcValue::TypeString:
      return "a string";
    case XmlRpcValue::TypeArray:
      return "a list";
    case XmlRpcValue::TypeStruct:
      return "a map";
    default:
      return "an unsupported type";
  }
}

XmlRpcValue& member(XmlRpcValue& entry, const std::string& key, const std::string& where) {
  if (!entry.hasMember(key)) throw std::runtime_error(where + ": missing key '" + key + "'");
  return entry[key];
}

std::string readString(XmlRpcValue& entry, const std::string& key, const std::string& where) {
  XmlRpcValue& v = member(entry, key, where);
  if (v.getType() != XmlRpcValue::TypeString) {
    throw std::runtime_error(where + ": '" + key + "' is " + typeName(v.getType()) + ", expected a string");
  }
  return static_cast<std::string>(v);
}

double readSeconds(XmlRpcValue& entry, const std::string& key, const std::string& where) {
  XmlRpcValue& v = member(entry, key, where);
  if (v.getType() == XmlRpcValue::TypeInt) return static_cast<int>(v);
  if (v.getType() == XmlRpcValue::TypeDouble) return static_cast<double>(v);
  throw std::runtime_error(where + ": '" + key + "' is " + typeName(v.getType()) + ", expected a number [s]");
}

int readPriority(XmlRpcValue& entry, const std::string& key, const std::string& where) {
  XmlRpcValue& v = member(entry, key, where);
  if (v.getType() != XmlRpcValue::TypeInt) {
    throw std::runtime_error(where + ": '" + key + "' is " + typeName(v.getType()) + ", expected an integer 0..255");
  }
  return static_cast<int>(v);
}

MuxEntry readEntry(XmlRpcValue& entry, const std::string& name, const std::string& where, bool stamped_default) {
  if (entry.getType() != XmlRpcValue::TypeStruct) {
    throw std::runtime_error(where + " is " + typeName(entry.getType()) +
                             ", expected a map {name, topic, timeout, priority}");
  }
  MuxEntry e;
  e.name = name;
  e.topic = readString(entry, "topic", where);
  e.timeout_s = readSeconds(entry, "timeout", where);
  e.priority = readPriority(entry, "priority", where);
  e.stamped = stamped_default;
  if (entry.hasMember("stamped")) {
    if (entry["stamped"].getType() != XmlRpcValue::TypeBoolean) {
      throw std::runtime_error(where + ": 'stamped' is " + typeName(entry["stamped"].getType()) + ", expected a bool");
    }
    e.stamped = static_cast<bool>(entry["stamped"]);
  }
  return e;
}

}  // namespace

std::vector<MuxEntry> parseMuxEntries(XmlRpcValue& value, const std::string& list_name, bool stamped_default) {
  std::vector<MuxEntry> entries;
  if (value.getType() == XmlRpcValue::TypeArray) {
    for (int i = 0; i < value.size(); ++i) {
      const std::string where = list_name + "[" + std::to_string(i) + "]";
      if (value[i].getType() != XmlRpcValue::TypeStruct) {
        throw std::runtime_error(where + " is " + typeName(value[i].getType()) +
                                 ", expected a map {name, topic, timeout, priority}");
      }
      const std::string name = readString(value[i], "name", where);
      entries.push_back(readEntry(value[i], name, where + " (" + name + ")", stamped_default));
    }
  } else if (value.getType() == XmlRpcValue::TypeStruct) {
    for (auto& item : value) {
      entries.push_back(readEntry(item.second, item.first, list_name + "/" + item.first, stamped_default));
    }
  } else {
    throw std::runtime_error(list_name + " is " + typeName(value.getType()) +
                             ", expected a list of {name, topic, timeout, priority}");
  }
  return entries;
}

std::string validateMuxOptions(const MuxOptions& options) {
  if (!std::isfinite(options.check_rate_hz) || options.check_rate_hz <= 0.0) {
    return "~check_rate is " + std::to_string(options.check_rate_hz) + ", expected a rate > 0 [Hz]";
  }
  if (options.frame_id.empty()) return "~frame_id is empty, expected a frame name";
  return {};
}

}  // namespace thorvald_twist_mux
