#pragma once

#include <cstddef>

#include "greenhouse_rail_nav/occupancy_map.h"

namespace greenhouse_rail_nav {

/// Removes speckle from a SLAM map: every 8-connected group of occupied cells (value >= occupied_value)
/// covering less than min_area_m2 is set free. Walls, rows, pots and clutter are larger than a few cells;
/// the false returns of a laser are single cells or pairs. Returns the number of cells cleared.
std::size_t removeSpeckle(OccupancyMap* map, double min_area_m2, int occupied_value = 65);

}  // namespace greenhouse_rail_nav
