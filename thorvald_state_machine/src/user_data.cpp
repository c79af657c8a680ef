#include "thorvald_state_machine/user_data.h"

namespace thorvald_state_machine {

std::vector<std::string> UserData::keys() const {
  std::vector<std::string> keys;
  keys.reserve(values_.size());
  for (const auto& entry : values_) keys.push_back(entry.first);
  return keys;
}

}  // namespace thorvald_state_machine
