#pragma once

#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

namespace thorvald_common {

/// Levenshtein distance: the fewest single-character insertions, deletions and substitutions that turn `a` into
/// `b`. Used to suggest the name a misspelt key, parameter or plugin meant. Header-only and ROS-free, so core
/// libraries use it without linking this package.
inline size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

/// The candidate nearest to `key` by edit distance (the first of equals), "" when there are no candidates.
/// `distance`, when given, receives its distance.
inline std::string nearestName(const std::string& key, const std::vector<std::string>& candidates,
                               size_t* distance = nullptr) {
  std::string best;
  size_t best_distance = 0;
  for (const auto& c : candidates) {
    const size_t d = editDistance(key, c);
    if (best.empty() || d < best_distance) {
      best = c;
      best_distance = d;
    }
  }
  if (distance) *distance = best_distance;
  return best;
}

}  // namespace thorvald_common
