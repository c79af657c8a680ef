#include "greenhouse_rail_nav/rail_set_layout.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace greenhouse_rail_nav {

std::string formatMetres(double value, int decimals) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(decimals);
  s << value;
  return s.str();
}

std::vector<RailSetPlan> planRailSets(const std::vector<HeadlandBoundary>& bounds, const SpacingEstimate& spacing,
                                      double spacing_m, const SideScan& left, const SideScan& right, double first_row_u,
                                      double last_row_u, int left_end_sets, int right_end_sets) {
  const double s = spacing_m;
  std::vector<RailSetPlan> plans;
  auto open_side = [&](const SideScan& scan, double u_out, double dir, const char* name, int end_sets) {
    const bool bounded = end_sets >= 0;
    const int n = bounded ? end_sets : static_cast<int>(std::floor((scan.floor_extent_m + 0.25) / s + 0.25));
    std::vector<RailSetPlan> extra;
    for (int k = 0; k < n; ++k) {
      extra.push_back({u_out + dir * (k + 0.5) * s, {}});
      if (!bounded)
        extra.back().reasons.push_back(std::string("no ") + name + " side wall found: placed by the spacing");
    }
    return extra;
  };
  if (!left.wall_found) {
    auto extra = open_side(left, first_row_u, -1.0, "left", left_end_sets);
    std::reverse(extra.begin(), extra.end());
    plans.insert(plans.end(), extra.begin(), extra.end());
  }
  for (std::size_t k = 0; k + 1 < bounds.size(); ++k) {
    const double gap = bounds[k + 1].u - bounds[k].u;
    const int n = spacing.sets_per_gap[k];
    std::vector<std::string> reasons;
    if (!spacing.gap_fits[k])
      reasons.push_back("gap of " + formatMetres(gap) + " m between " + bounds[k].name + " and " + bounds[k + 1].name +
                        " is not a whole number of spacings (" + formatMetres(s) + " m)");
    if (spacing.gap_ambiguous[k])
      reasons.push_back("gap of " + formatMetres(gap) + " m fits more than one number of rail sets");
    for (const auto* b : {&bounds[k], &bounds[k + 1]})
      if (!b->heading_ok) reasons.push_back(b->name + " disagrees in heading with the other rows");
    for (int j = 0; j < n; ++j) plans.push_back({bounds[k].u + (j + 0.5) * gap / n, reasons});
  }
  if (!right.wall_found) {
    const auto extra = open_side(right, last_row_u, +1.0, "right", right_end_sets);
    plans.insert(plans.end(), extra.begin(), extra.end());
  }
  return plans;
}

}  // namespace greenhouse_rail_nav
