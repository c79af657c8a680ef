#pragma once

#include <string>
#include <vector>

#include "greenhouse_rail_nav/headland_scan.h"
#include "greenhouse_rail_nav/rail_spacing.h"

namespace greenhouse_rail_nav {

/// A line across the headland that bounds rail sets: a side wall or a row, at u [m] across the greenhouse.
struct HeadlandBoundary {
  double u = 0.0;
  std::string name;
  bool heading_ok = true;  ///< its direction agrees with the other rows
};

/// A rail set's place across the headland (u [m]) and why it is uncertain (empty: no reason of its own).
struct RailSetPlan {
  double u = 0.0;
  std::vector<std::string> reasons;
};

/// Where the rail sets lie across the headland: spacing.sets_per_gap[k] sets spread evenly over the gap
/// between bounds[k] and bounds[k + 1] (sorted by u), each with the reasons its gap gives to doubt it (a
/// gap that is no whole number of spacings, or fits more than one, a boundary off the rows' heading); on a
/// side without a wall, sets spacing_m apart beyond the outermost row: left_end_sets (right_end_sets) of
/// them when the rear wall's end bounds that side (>= 0), else as far as the mapped floor goes, all
/// uncertain. Returned in order of u.
std::vector<RailSetPlan> planRailSets(const std::vector<HeadlandBoundary>& bounds, const SpacingEstimate& spacing,
                                      double spacing_m, const SideScan& left, const SideScan& right, double first_row_u,
                                      double last_row_u, int left_end_sets = -1, int right_end_sets = -1);

/// "a.bc" with the given decimals, for messages.
std::string formatMetres(double value, int decimals = 2);

}  // namespace greenhouse_rail_nav
