#pragma once

#include <cstddef>

#include "thorvald_map/occupancy_grid.h"

namespace greenhouse_rail_nav {

/// Removes speckle from a SLAM map: every group of occupied cells (value >= occupied_value) covering less than
/// min_area_m2 is set free. A group is 8-connected, or with link_radius_m > one cell, every cell within that
/// distance of another of the group belongs to it. Walls, rows, pots and clutter are larger than a few cells; the
/// false returns of a laser are single cells or pairs, and they are isolated. A face the lidar saw at a grazing
/// angle is drawn as dots a few cells apart: linked, they are one long group, not many small ones. Returns the
/// number of cells cleared.
std::size_t removeSpeckle(thorvald_map::OccupancyGrid* map, double min_area_m2, double link_radius_m = 0.0,
                          int occupied_value = 65);

}  // namespace greenhouse_rail_nav
