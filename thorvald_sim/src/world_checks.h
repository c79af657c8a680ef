#pragma once

#include <cmath>
#include <stdexcept>
#include <string>

namespace thorvald_sim {
namespace detail {

/// Throws std::invalid_argument unless `v` is a positive, finite length; `key` names the parameter.
inline void requirePositive(double v, const char* key) {
  if (!(v > 0.0) || !std::isfinite(v))
    throw std::invalid_argument(std::string(key) + " must be a positive number of metres, got " + std::to_string(v));
}

}  // namespace detail
}  // namespace thorvald_sim
