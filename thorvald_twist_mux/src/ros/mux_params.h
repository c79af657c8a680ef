#pragma once

#include <string>

#include <xmlrpcpp/XmlRpcValue.h>

#include "thorvald_twist_mux/mux_config.h"

namespace thorvald_twist_mux {

/// Options of the node beyond twist_mux's, all off by default where they change behaviour.
struct MuxOptions {
  bool zero_on_loss = false;           ///< one zero twist when the driving input times out or a lock masks it
  bool use_stamped = false;            ///< inputs (unless an entry says `stamped`) and output are TwistStamped
  bool publish_marker = false;         ///< RViz arrow of the output on `~marker`
  std::string frame_id = "base_link";  ///< frame of the marker and of stamped output made from plain input
  double check_rate_hz = 50.0;         ///< [Hz] rate at which timeouts and watchdogs are checked (status, zero twist)
};

/// Reads one list parameter (`topics` or `locks`) in either form twist_mux accepts: an array of structs with
/// `name`, or a struct whose keys are the names. `timeout` may be an int or a double. Throws std::runtime_error
/// naming the parameter, the entry and the key on a missing or mistyped key. `stamped_default` fills `stamped`
/// when the entry has no `stamped` key.
std::vector<MuxEntry> parseMuxEntries(XmlRpc::XmlRpcValue& value, const std::string& list_name, bool stamped_default);

/// Validates the rate and frame of `options`; returns an error message or an empty string.
std::string validateMuxOptions(const MuxOptions& options);

}  // namespace thorvald_twist_mux
