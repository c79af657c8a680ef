#pragma once

#include <cstddef>
#include <string>
#include <vector>

namespace thorvald_base {

/// Levenshtein distance: the fewest single-character insertions, deletions and substitutions that turn `a` into
/// `b`. Used to suggest the name a misspelt key meant.
size_t editDistance(const std::string& a, const std::string& b);

/// The candidate nearest to `key` by edit distance (the first of equals), "" when there are no candidates.
/// `distance`, when given, receives its distance.
std::string nearestName(const std::string& key, const std::vector<std::string>& candidates, size_t* distance = nullptr);

}  // namespace thorvald_base
