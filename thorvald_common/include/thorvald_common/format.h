#pragma once

#include <cstdarg>
#include <cstdio>
#include <string>

namespace thorvald_common {

/// printf-style text (log lines, failure reasons), cut at 511 characters. Header-only and ROS-free.
inline std::string format(const char* fmt, ...) __attribute__((format(printf, 1, 2)));
inline std::string format(const char* fmt, ...) {
  char text[512];
  va_list args;
  va_start(args, fmt);
  std::vsnprintf(text, sizeof(text), fmt, args);
  va_end(args);
  return text;
}

}  // namespace thorvald_common
