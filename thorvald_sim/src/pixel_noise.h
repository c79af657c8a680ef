#pragma once

// Fast per-pixel noise for the camera images (internal to thorvald_sim's library).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace thorvald_sim {

/// The standard normal quantile function at 4097 equally spaced probabilities, the two ends moved in by half a
/// step (so they are finite: +-3.67): inverse-CDF sampling with linear interpolation between them gives normal
/// deviates without a logarithm per pixel (variance within 0.2 % of 1, tails cut at 3.67 sigma).
inline const std::vector<double>& normalQuantiles() {
  static const std::vector<double> table = [] {
    constexpr int kSteps = 4096;
    std::vector<double> q(kSteps + 1);
    for (int i = 0; i <= kSteps; ++i) {
      const double p = std::clamp(static_cast<double>(i), 0.5, kSteps - 0.5) / kSteps;
      double lo = -10.0, hi = 10.0;  // Phi(x) = erfc(-x / sqrt 2) / 2 is increasing: bisect
      for (int it = 0; it < 60; ++it) {
        const double mid = 0.5 * (lo + hi);
        (0.5 * std::erfc(-mid / std::sqrt(2.0)) < p ? lo : hi) = mid;
      }
      q[i] = 0.5 * (lo + hi);
    }
    return q;
  }();
  return table;
}

// A fast generator for the per-pixel noise of one frame, seeded from the caller's engine (so the frame stays
// reproducible from the sensor's seed): one splitmix64 draw per pixel gives both its dropout (a 24-bit uniform) and
// its normal deviate (the quantile table: 12 bits pick the step, 28 bits where in it).
class PixelNoise {
 public:
  static constexpr int kUniformBits = 24;
  explicit PixelNoise(std::mt19937& rng) : quantiles_(normalQuantiles().data()) {
    const uint64_t high = rng();  // two statements: the order of the draws is fixed
    state_ = (high << 32) | rng();
  }
  /// A draw; uniform(draw) and normal(draw) use disjoint bits of it.
  uint64_t next() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  /// Uniform in [0, 2^24): compare with p 2^24 for an event of probability p.
  static uint32_t uniform(uint64_t draw) { return static_cast<uint32_t>(draw & ((1u << kUniformBits) - 1)); }
  double normal(uint64_t draw) const {
    const size_t i = draw >> 52;                                               // 12 bits: the step
    const double f = ((draw >> kUniformBits) & ((1u << 28) - 1)) * 0x1.0p-28;  // 28 bits: where in the step
    return quantiles_[i] + f * (quantiles_[i + 1] - quantiles_[i]);
  }

 private:
  const double* quantiles_;
  uint64_t state_ = 0;
};

}  // namespace thorvald_sim
