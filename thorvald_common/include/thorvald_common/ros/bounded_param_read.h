#pragma once

#include <xmlrpcpp/XmlRpcValue.h>

#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace thorvald_common {

/// Bounds on one read from the parameter server, checked on the master's reply before anything is parsed or
/// expanded: a few hundred bytes of YAML aliases loaded with `rosparam load` can expand to gigabytes there.
struct ParamReadBounds {
  size_t max_bytes = 1 << 20;  ///< the reply, XML-RPC encoded [bytes]
  size_t max_values = 20000;   ///< map entries, list items and scalars together
  size_t max_depth = 8;        ///< nesting of maps and lists (a robot file nests 2: group, module)
};

/// A read that exceeded its bounds; what() says which ("expands to more than 20000 values", "takes more than
/// 1048576 bytes", "nests deeper than 8 levels").
class ParamTooLarge : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A read stopped because the node is shutting down (SIGINT, SIGTERM, ros::shutdown).
class ParamReadInterrupted : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class XmlRpcBound { kNone, kValues, kDepth };

/// The first bound an XML-RPC encoded value (or a whole reply) exceeds, found without parsing it: more than
/// `max_values` <value> elements, or maps and lists nested deeper than `max_depth`.
XmlRpcBound exceededBound(const std::string& xml, size_t max_values, size_t max_depth);

/// Reads parameter `key` (a resolved name) from the ROS master as ros::param::get does, but bounded: the reply is
/// refused past `bounds.max_bytes` (announced or received), past `bounds.max_values` values or `bounds.max_depth`
/// levels of nesting, before it is parsed, and the read stops when the node shuts down (checked every 100 ms).
/// Returns false when the parameter does not exist. Throws ParamTooLarge, ParamReadInterrupted, or
/// std::runtime_error when the master cannot be reached or answers an error.
bool getParamBounded(const std::string& key, XmlRpc::XmlRpcValue& value, const ParamReadBounds& bounds);

/// Every parameter name on the server (as ros::param::getParamNames), or nothing when the list is larger than
/// `max_bytes` encoded. Throws ParamReadInterrupted, or std::runtime_error when the master cannot be reached.
std::optional<std::vector<std::string>> getParamNamesBounded(size_t max_bytes);

}  // namespace thorvald_common
