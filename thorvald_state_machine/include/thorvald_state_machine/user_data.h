#pragma once

#include <any>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace thorvald_state_machine {

/// Thrown when a state reads a user-data key that is missing or holds another type.
class UserDataError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Typed key/value store shared by the states of one machine run (SMACH's "userdata").
/// Values are copied in and out; a key keeps the type it was first written with until erased.
class UserData {
 public:
  /// Stores `value` under `key`, replacing any previous value of the same type.
  /// Throws UserDataError when the key already holds a value of another type.
  template <typename T>
  void set(const std::string& key, T value) {
    auto it = values_.find(key);
    if (it != values_.end() && it->second.type() != typeid(T)) {
      throw UserDataError("user data key '" + key + "' holds a " + it->second.type().name() + ", not a " +
                          typeid(T).name());
    }
    values_[key] = std::move(value);
  }

  /// The value under `key`; throws UserDataError naming the key when missing or of another type.
  template <typename T>
  const T& get(const std::string& key) const {
    auto it = values_.find(key);
    if (it == values_.end()) throw UserDataError("user data key '" + key + "' is missing");
    const T* value = std::any_cast<T>(&it->second);
    if (value == nullptr) {
      throw UserDataError("user data key '" + key + "' holds a " + it->second.type().name() + ", not a " +
                          typeid(T).name());
    }
    return *value;
  }

  /// The value under `key`, or `fallback` when the key is missing (a type mismatch still throws).
  template <typename T>
  T getOr(const std::string& key, T fallback) const {
    return has(key) ? get<T>(key) : fallback;
  }

  bool has(const std::string& key) const { return values_.count(key) > 0; }
  void erase(const std::string& key) { values_.erase(key); }
  void clear() { values_.clear(); }
  std::vector<std::string> keys() const;

 private:
  std::map<std::string, std::any> values_;
};

}  // namespace thorvald_state_machine
