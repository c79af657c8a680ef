#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "greenhouse_rail_nav/pose2d.h"

namespace greenhouse_rail_nav {

/// Where the lidar's beams ended inside each cell of a map, when the map's maker kept it (thorvald_navigation's
/// headland_mapper writes it beside the map, named by the YAML's `wall_surface` key): per cell the mean end point
/// in the map frame and how many ends it holds. An occupancy grid says which cell holds a wall's face; this says
/// where inside the cells the face is. Same cell order as OccupancyMap::cells; empty when the map has none.
struct CellSurface {
  std::vector<Eigen::Vector2f> mean_m;  ///< mean beam end point in the map frame [m]; unused where hits is 0
  std::vector<float> hits;              ///< beam ends counted in the cell (0: none)
  bool empty() const { return hits.empty(); }
};

/// A 2D occupancy grid laid out like nav_msgs/OccupancyGrid: row-major, row 0 at the origin, cell values
/// 0 (free), 100 (occupied), -1 (unknown), or anything in between.
struct OccupancyMap {
  static constexpr std::int8_t kFree = 0;
  static constexpr std::int8_t kOccupied = 100;
  static constexpr std::int8_t kUnknown = -1;

  int width = 0;             ///< [cells] along the origin's x axis
  int height = 0;            ///< [cells] along the origin's y axis
  double resolution = 0.05;  ///< [m/cell]
  Pose2D origin;             ///< pose of cell (0,0)'s lower-left corner in the map frame
  std::vector<std::int8_t> cells;
  CellSurface surface;  ///< optional: empty, or one entry per cell

  OccupancyMap() = default;
  OccupancyMap(int width_cells, int height_cells, double resolution_m, const Pose2D& origin_pose,
               std::int8_t fill = kUnknown);

  bool inside(int col, int row) const { return col >= 0 && row >= 0 && col < width && row < height; }
  std::int8_t at(int col, int row) const { return cells[static_cast<std::size_t>(row) * width + col]; }
  std::int8_t& at(int col, int row) { return cells[static_cast<std::size_t>(row) * width + col]; }
  /// Centre of a cell in the map frame [m].
  Eigen::Vector2d cellCentre(int col, int row) const;
  /// The cell that holds a map-frame point; false if outside the grid.
  bool worldToCell(const Eigen::Vector2d& p, int* col, int* row) const;
  /// Value at a map-frame point, kUnknown outside the grid.
  std::int8_t valueAt(const Eigen::Vector2d& p) const;
  /// Size along the origin's axes [m].
  double widthMeters() const { return width * resolution; }
  double heightMeters() const { return height * resolution; }
};

}  // namespace greenhouse_rail_nav
