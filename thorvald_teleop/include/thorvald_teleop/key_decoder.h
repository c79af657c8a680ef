#pragma once

#include <string>
#include <vector>

namespace thorvald_teleop {

/// A key as a terminal sends it: arrows arrive as escape sequences, everything else as one byte.
struct KeyPress {
  enum class Kind { kCharacter, kUp, kDown, kLeft, kRight };
  Kind kind = Kind::kCharacter;
  char character = 0;  ///< for kCharacter
};

/// Turns bytes read from a terminal in raw mode into key presses. Understands the arrow sequences ESC [ A..D and
/// ESC O A..D (application cursor mode); a sequence split across reads is completed by the next feed; other
/// escape sequences are dropped.
class KeyDecoder {
 public:
  std::vector<KeyPress> feed(const std::string& bytes);

 private:
  std::string pending_;  ///< an incomplete escape sequence
};

}  // namespace thorvald_teleop
