#pragma once

#include <Eigen/Core>

#include "thorvald_map/occupancy_grid.h"

namespace greenhouse_rail_nav {

/// The paper's virtual wall: a grid with the map's geometry where every cell beyond the headland edge
/// (the rows' side of the line through edge_start and edge_end, shifted by margin_m into the rows) is
/// occupied and every other cell free. A costmap that takes it as an obstacle layer keeps the robot on
/// the headland floor while it drives between rail sets.
thorvald_map::OccupancyGrid makeKeepOutGrid(const thorvald_map::OccupancyGrid& map, const Eigen::Vector2d& edge_start,
                                            const Eigen::Vector2d& edge_end, const Eigen::Vector2d& into_rows,
                                            double margin_m);

}  // namespace greenhouse_rail_nav
