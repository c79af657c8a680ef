#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace greenhouse_rail_nav {

/// Which metres of a rail set were passed with the lights on: the lamps' position along the rails is reported tick
/// by tick with the lights' state, in bins of `bin_m`. A stop with the lights off and the robot braking on leaves a
/// gap until the robot comes back over it with the lights on.
class LitCoverage {
 public:
  explicit LitCoverage(double bin_m = 0.05) : bin_m_(bin_m) {}
  /// The robot moved from `from_m` to `to_m` along the rails [m] with the lights `on`.
  void add(double from_m, double to_m, bool on) {
    end_m_ = std::max({end_m_, from_m, to_m});
    if (!on) return;
    const double lo = std::max(0.0, std::min(from_m, to_m)), hi = std::max(from_m, to_m);
    const auto last = static_cast<std::size_t>(std::floor(hi / bin_m_));
    if (lit_.size() <= last) lit_.resize(last + 1, false);
    for (auto i = static_cast<std::size_t>(std::floor(lo / bin_m_)); i <= last; ++i) lit_[i] = true;
  }
  /// The farthest point reached [m].
  double end() const { return end_m_; }
  /// The farthest lit point such that everything before it is lit [m].
  double litUpTo() const {
    std::size_t i = 0;
    while (i < lit_.size() && lit_[i]) ++i;
    return std::min(end_m_, i * bin_m_);
  }
  /// Share of [0, end()] that was lit, in [0, 1] (1 with nothing driven).
  double fraction() const {
    const auto bins = static_cast<std::size_t>(std::ceil(end_m_ / bin_m_ - 1e-9));
    if (bins == 0) return 1.0;
    std::size_t n = 0;
    for (std::size_t i = 0; i < bins && i < lit_.size(); ++i) n += lit_[i] ? 1 : 0;
    return static_cast<double>(n) / bins;
  }

 private:
  double bin_m_;
  double end_m_ = 0.0;
  std::vector<bool> lit_;
};

}  // namespace greenhouse_rail_nav
