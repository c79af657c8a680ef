#pragma once

// How kind a simulated sensor is: `ideal` (the simulator's first sensor models: Gaussian noise, random dropouts)
// or `datasheet` (the error models of the named device, with figures from its datasheet or the project's papers;
// README "Sensor models and realism").

#include <optional>
#include <string>

namespace thorvald_sim {

enum class Realism { kIdeal, kDatasheet };

inline const char* realismName(Realism r) { return r == Realism::kIdeal ? "ideal" : "datasheet"; }

/// The profile named `name`, or nothing for an unknown name.
inline std::optional<Realism> realismFromName(const std::string& name) {
  if (name == "ideal") return Realism::kIdeal;
  if (name == "datasheet") return Realism::kDatasheet;
  return std::nullopt;
}

}  // namespace thorvald_sim
