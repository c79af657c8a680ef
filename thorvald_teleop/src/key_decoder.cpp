#include "thorvald_teleop/key_decoder.h"

namespace thorvald_teleop {
namespace {

constexpr char kEscape = 0x1b;

bool arrowKind(char final_byte, KeyPress::Kind& kind) {
  switch (final_byte) {
    case 'A':
      kind = KeyPress::Kind::kUp;
      return true;
    case 'B':
      kind = KeyPress::Kind::kDown;
      return true;
    case 'C':
      kind = KeyPress::Kind::kRight;
      return true;
    case 'D':
      kind = KeyPress::Kind::kLeft;
      return true;
    default:
      return false;
  }
}

}  // namespace

std::vector<KeyPress> KeyDecoder::feed(const std::string& bytes) {
  std::vector<KeyPress> keys;
  for (char c : bytes) {
    if (pending_.empty()) {
      if (c == kEscape) {
        pending_.push_back(c);
      } else {
        keys.push_back({KeyPress::Kind::kCharacter, c});
      }
      continue;
    }
    pending_.push_back(c);
    if (pending_.size() == 2) {
      if (c != '[' && c != 'O') {  // not a CSI/SS3 sequence: a lone escape then this key
        pending_.clear();
        keys.push_back({KeyPress::Kind::kCharacter, kEscape});
        if (c == kEscape) {
          pending_.push_back(c);
        } else {
          keys.push_back({KeyPress::Kind::kCharacter, c});
        }
      }
      continue;
    }
    // A CSI sequence ends with a byte in 0x40..0x7e; parameters (digits, ';') come before it.
    if (c >= 0x40 && c <= 0x7e) {
      KeyPress::Kind kind;
      if (pending_.size() == 3 && arrowKind(c, kind)) keys.push_back({kind, 0});
      pending_.clear();
    } else if (pending_.size() > 16) {
      pending_.clear();  // malformed: drop it
    }
  }
  return keys;
}

}  // namespace thorvald_teleop
