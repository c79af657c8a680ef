#pragma once

#include <vector>

#include <Eigen/Core>

#include "thorvald_map/occupancy_grid.h"

namespace greenhouse_rail_nav {

/// A group of neighbouring occupied cells, as map-frame cell centres [m].
struct CellCluster {
  std::vector<Eigen::Vector2d> points;
};

/// Groups occupied cells (value >= occupied_value) into clusters: two cells belong together when their
/// centres are at most link_radius_m apart, which joins the dotted lines a row of plants leaves in a map.
/// Clusters with fewer than min_cells cells are dropped.
std::vector<CellCluster> clusterOccupiedCells(const thorvald_map::OccupancyGrid& map, double link_radius_m,
                                              std::size_t min_cells, int occupied_value = 65);

}  // namespace greenhouse_rail_nav
