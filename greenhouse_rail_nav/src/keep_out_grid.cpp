#include "greenhouse_rail_nav/keep_out_grid.h"

namespace greenhouse_rail_nav {

thorvald_map::OccupancyGrid makeKeepOutGrid(const thorvald_map::OccupancyGrid& map, const Eigen::Vector2d& edge_start,
                                            const Eigen::Vector2d& edge_end, const Eigen::Vector2d& into_rows,
                                            double margin_m) {
  thorvald_map::OccupancyGrid grid(map.width, map.height, map.resolution_m, map.origin, thorvald_map::kFree);
  // Normal of the edge line, pointing into the rows.
  Eigen::Vector2d along = edge_end - edge_start;
  Eigen::Vector2d normal = along.norm() > 1e-9 ? Eigen::Vector2d(-along.y(), along.x()).normalized() : into_rows;
  if (normal.dot(into_rows) < 0.0) normal = -normal;
  // The signed distance is affine in (col, row): step it instead of transforming every cell.
  const Eigen::Vector2d c00 = map.cellCentre(0, 0);
  const double d00 = normal.dot(c00 - edge_start) - margin_m;
  const double d_col = normal.dot(map.cellCentre(1, 0) - c00);
  const double d_row = normal.dot(map.cellCentre(0, 1) - c00);
  for (int r = 0; r < map.height; ++r) {
    for (int c = 0; c < map.width; ++c) {
      if (d00 + c * d_col + r * d_row > 0.0) grid.at(c, r) = thorvald_map::kOccupied;
    }
  }
  return grid;
}

}  // namespace greenhouse_rail_nav
