#include "greenhouse_rail_nav/rail_spacing.h"

#include <algorithm>
#include <cmath>

namespace greenhouse_rail_nav {
namespace {

struct Pattern {
  std::vector<int> counts;
  double spacing = 0.0;
  double max_residual = 0.0;
};

Pattern fitCounts(const std::vector<double>& gaps, std::vector<int> counts) {
  double num = 0.0, den = 0.0;
  for (std::size_t i = 0; i < gaps.size(); ++i) {
    num += counts[i] * gaps[i];
    den += static_cast<double>(counts[i]) * counts[i];
  }
  Pattern p;
  p.counts = std::move(counts);
  p.spacing = den > 0.0 ? num / den : 0.0;
  for (std::size_t i = 0; i < gaps.size(); ++i)
    p.max_residual = std::max(p.max_residual, std::abs(gaps[i] - p.counts[i] * p.spacing));
  return p;
}

std::vector<int> countsFor(const std::vector<double>& gaps, double spacing) {
  std::vector<int> counts;
  for (const double g : gaps) counts.push_back(std::max(1, static_cast<int>(std::lround(g / spacing))));
  return counts;
}

}  // namespace

SpacingEstimate estimateSpacing(const std::vector<double>& gaps_m, double configured_m, double search_ratio,
                                double tolerance_m) {
  SpacingEstimate out;
  const double lo = configured_m / search_ratio, hi = configured_m * search_ratio;
  // Every pattern of counts reachable by a spacing in the range, refitted on the gaps it fits; the
  // patterns fitting the most gaps win (a false or missed row spoils two gaps, not the whole estimate).
  std::vector<Pattern> best;
  std::size_t best_fit = 0;
  if (!gaps_m.empty()) {
    const double largest = *std::max_element(gaps_m.begin(), gaps_m.end());
    const double step = std::max(1e-4, 0.25 * tolerance_m / (1.0 + largest / lo));
    std::vector<int> last;
    for (double s = lo; s <= hi; s += step) {
      std::vector<int> counts = countsFor(gaps_m, s);
      if (counts == last) continue;
      last = counts;
      // Least squares over every gap with these counts, then refitted on the gaps that fit.
      double spacing = fitCounts(gaps_m, counts).spacing;
      std::vector<bool> fits(gaps_m.size());
      std::size_t n_fit = 0;
      for (int pass = 0; pass < 3; ++pass) {
        double num = 0.0, den = 0.0;
        n_fit = 0;
        for (std::size_t i = 0; i < gaps_m.size(); ++i) {
          fits[i] = std::abs(gaps_m[i] - counts[i] * spacing) <= tolerance_m;
          if (!fits[i]) continue;
          ++n_fit;
          num += counts[i] * gaps_m[i];
          den += static_cast<double>(counts[i]) * counts[i];
        }
        if (den <= 0.0) break;
        spacing = num / den;
      }
      if (n_fit == 0 || spacing < lo || spacing > hi) continue;
      Pattern p;
      p.counts = counts;
      p.spacing = spacing;
      for (std::size_t i = 0; i < gaps_m.size(); ++i) {
        if (fits[i]) p.max_residual = std::max(p.max_residual, std::abs(gaps_m[i] - counts[i] * spacing));
      }
      if (n_fit > best_fit) {
        best_fit = n_fit;
        best.clear();
      }
      if (n_fit == best_fit &&
          std::none_of(best.begin(), best.end(), [&](const Pattern& f) { return f.counts == p.counts; }))
        best.push_back(p);
    }
  }
  out.hypotheses = static_cast<int>(best.size());
  out.regular = !best.empty() && best_fit == gaps_m.size();
  Pattern chosen;
  if (best.empty()) {
    chosen = fitCounts(gaps_m, countsFor(gaps_m, configured_m));
    if (gaps_m.empty()) chosen.spacing = configured_m;
  } else {
    chosen = *std::min_element(best.begin(), best.end(), [&](const Pattern& a, const Pattern& b) {
      return std::abs(a.spacing - configured_m) < std::abs(b.spacing - configured_m);
    });
  }
  out.spacing_m = chosen.spacing;
  // Counts of the gaps that do not fit: the nearest whole number of the chosen spacing.
  out.sets_per_gap = countsFor(gaps_m, chosen.spacing);
  for (std::size_t i = 0; i < gaps_m.size(); ++i) {
    const double r = std::abs(gaps_m[i] - out.sets_per_gap[i] * chosen.spacing);
    out.residual_m.push_back(r);
    out.gap_fits.push_back(r <= tolerance_m);
    bool ambiguous = false;
    for (const auto& f : best) ambiguous = ambiguous || f.counts[i] != out.sets_per_gap[i];
    out.gap_ambiguous.push_back(ambiguous);
  }
  return out;
}

}  // namespace greenhouse_rail_nav
