#include "greenhouse_rail_nav/occupancy_map.h"

#include <cmath>

namespace greenhouse_rail_nav {

OccupancyMap::OccupancyMap(int width_cells, int height_cells, double resolution_m, const Pose2D& origin_pose,
                           std::int8_t fill)
    : width(width_cells),
      height(height_cells),
      resolution(resolution_m),
      origin(origin_pose),
      cells(static_cast<std::size_t>(width_cells) * height_cells, fill) {}

Eigen::Vector2d OccupancyMap::cellCentre(int col, int row) const {
  return origin.transformPoint({(col + 0.5) * resolution, (row + 0.5) * resolution});
}

bool OccupancyMap::worldToCell(const Eigen::Vector2d& p, int* col, int* row) const {
  const Eigen::Vector2d local = origin.inverse().transformPoint(p);
  const double c = std::floor(local.x() / resolution);
  const double r = std::floor(local.y() / resolution);
  if (!(c >= 0.0 && r >= 0.0 && c < width && r < height)) return false;
  *col = static_cast<int>(c);
  *row = static_cast<int>(r);
  return true;
}

std::int8_t OccupancyMap::valueAt(const Eigen::Vector2d& p) const {
  int c = 0, r = 0;
  return worldToCell(p, &c, &r) ? at(c, r) : kUnknown;
}

}  // namespace greenhouse_rail_nav
