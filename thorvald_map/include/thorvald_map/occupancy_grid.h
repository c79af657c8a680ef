#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "thorvald_base/pose2d.h"
#include "thorvald_map/wall_surface.h"

namespace thorvald_map {

/// Occupancy values as nav_msgs/OccupancyGrid writes them (anything in between is a probability in percent).
constexpr std::int8_t kUnknown = -1;
constexpr std::int8_t kFree = 0;
constexpr std::int8_t kOccupied = 100;

/// A 2D occupancy grid laid out like nav_msgs/OccupancyGrid: row-major, cell (0, 0) has its lower-left corner at
/// `origin`, columns go along the origin's x axis and rows along its y axis. Values -1 (unknown), 0 (free) .. 100
/// (occupied). `surface` optionally keeps where inside each cell the beams ended (the mapper's wall surface).
struct OccupancyGrid {
  int width = 0;                  ///< [cells] along the origin's x axis
  int height = 0;                 ///< [cells] along the origin's y axis
  double resolution_m = 0.05;     ///< [m/cell]
  thorvald_base::Pose2D origin;   ///< pose of cell (0, 0)'s lower-left corner in the grid's parent frame
  std::vector<std::int8_t> data;  ///< width x height values, row 0 first
  WallSurface surface;            ///< optional: empty, or one entry per cell

  OccupancyGrid() = default;
  OccupancyGrid(int width_cells, int height_cells, double resolution, const thorvald_base::Pose2D& origin_pose,
                std::int8_t fill = kUnknown);
  /// An unrotated grid with its origin at (origin_x_m, origin_y_m).
  OccupancyGrid(int width_cells, int height_cells, double resolution, double origin_x_m, double origin_y_m,
                std::int8_t fill = kUnknown)
      : OccupancyGrid(width_cells, height_cells, resolution, thorvald_base::Pose2D(origin_x_m, origin_y_m, 0.0), fill) {
  }

  bool inside(int cx, int cy) const { return cx >= 0 && cy >= 0 && cx < width && cy < height; }
  std::size_t index(int cx, int cy) const {
    return static_cast<std::size_t>(cy) * static_cast<std::size_t>(width) + static_cast<std::size_t>(cx);
  }
  std::int8_t at(int cx, int cy) const { return data[index(cx, cy)]; }
  std::int8_t& at(int cx, int cy) { return data[index(cx, cy)]; }

  /// The cell holding a point of the parent frame (may lie outside the grid).
  Eigen::Vector2i cellOf(const Eigen::Vector2d& p) const {
    const Eigen::Vector2d local = toGrid(p);
    return {static_cast<int>(std::floor(local.x() / resolution_m)),
            static_cast<int>(std::floor(local.y() / resolution_m))};
  }
  /// The cell holding a point of the parent frame; false (and *cx, *cy untouched) outside the grid.
  bool worldToCell(const Eigen::Vector2d& p, int* cx, int* cy) const;
  /// Centre of a cell in the parent frame [m].
  Eigen::Vector2d cellCentre(int cx, int cy) const {
    const Eigen::Vector2d local((cx + 0.5) * resolution_m, (cy + 0.5) * resolution_m);
    if (origin.yaw == 0.0) return {origin.x + local.x(), origin.y + local.y()};
    return origin.transformPoint(local);
  }
  /// Value at a point of the parent frame, kUnknown outside the grid.
  std::int8_t valueAt(const Eigen::Vector2d& p) const;
  /// Size along the origin's axes [m].
  double widthMeters() const { return width * resolution_m; }
  double heightMeters() const { return height * resolution_m; }
  /// Empty string when the grid (and its surface, if any) is usable, else what is wrong with it.
  std::string check() const;

 private:
  /// A point of the parent frame in the grid's own frame (origin at cell (0, 0)'s corner) [m].
  Eigen::Vector2d toGrid(const Eigen::Vector2d& p) const {
    if (origin.yaw == 0.0) return {p.x() - origin.x, p.y() - origin.y};
    return origin.inverse().transformPoint(p);
  }
};

}  // namespace thorvald_map
