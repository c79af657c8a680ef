#pragma once

#include <string>
#include <vector>

namespace greenhouse_rail_nav {

/// The rail-set spacing read from the regular pattern of rows and walls across the headland.
struct SpacingEstimate {
  double spacing_m = 0.0;           ///< least-squares spacing given the set counts [m]
  std::vector<int> sets_per_gap;    ///< rail sets between each pair of neighbouring lines
  std::vector<double> residual_m;   ///< |gap - sets * spacing| per gap [m]
  std::vector<bool> gap_fits;       ///< residual within the tolerance
  std::vector<bool> gap_ambiguous;  ///< another spacing in the search range fits with a different count here
  int hypotheses = 0;               ///< distinct set-count patterns fitting the most gaps (1 = unambiguous)
  bool regular = false;             ///< the chosen pattern fits every gap within the tolerance
};

/// Finds the spacing s in [configured / ratio, configured * ratio] such that as many gaps between
/// neighbouring lines (rows, side walls) as possible are close to a whole number (>= 1) of spacings (least
/// squares over the gaps that fit). When more than one pattern of counts fits that many gaps, the one whose
/// spacing is nearest the configured one is taken and the gaps where the patterns disagree are marked
/// ambiguous; the gaps that do not fit are marked too. gaps_m must be positive.
SpacingEstimate estimateSpacing(const std::vector<double>& gaps_m, double configured_m, double search_ratio,
                                double tolerance_m);

}  // namespace greenhouse_rail_nav
