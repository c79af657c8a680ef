#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numeric>
#include <vector>

namespace thorvald_common {

/// Statistics that the benchmarks print, one convention for the whole workspace. Every function takes the
/// samples by value or const reference and leaves the caller's order alone; none needs ROS.
/// Of no samples, every statistic is 0, so that a RESULT line stays valid JSON; a benchmark prints the sample
/// count beside its statistics, which tells an empty run from a zero.

/// The `q`-quantile (q in [0, 1], e.g. 0.95 for p95) by the nearest rank on the sorted samples: the sample at
/// index round(q * (n - 1)), halves rounded up. p0 is the minimum, p100 the maximum, p50 of an odd count the
/// median; no interpolation, so the result is always one of the samples. `q` outside [0, 1] is clamped.
inline double percentile(std::vector<double> samples, double q) {
  if (samples.empty()) return 0.0;
  std::sort(samples.begin(), samples.end());
  const double clamped = std::min(1.0, std::max(0.0, q));
  const auto index = static_cast<std::size_t>(clamped * static_cast<double>(samples.size() - 1) + 0.5);
  return samples[std::min(samples.size() - 1, index)];
}

/// Arithmetic mean.
inline double mean(const std::vector<double>& samples) {
  if (samples.empty()) return 0.0;
  return std::accumulate(samples.begin(), samples.end(), 0.0) / static_cast<double>(samples.size());
}

/// Root mean square (about 0, not about the mean): the size of an error whose samples are signed.
inline double rms(const std::vector<double>& samples) {
  if (samples.empty()) return 0.0;
  double sum_sq = 0.0;
  for (const double v : samples) sum_sq += v * v;
  return std::sqrt(sum_sq / static_cast<double>(samples.size()));
}

/// Largest sample.
inline double max(const std::vector<double>& samples) {
  if (samples.empty()) return 0.0;
  return *std::max_element(samples.begin(), samples.end());
}

}  // namespace thorvald_common
