#include "thorvald_map/occupancy_grid.h"

namespace thorvald_map {

std::string WallSurface::check(std::size_t cells) const {
  if (hits.size() != cells || mean_m.size() != cells)
    return "wall surface has " + std::to_string(hits.size()) + " cells, the grid " + std::to_string(cells);
  return {};
}

OccupancyGrid::OccupancyGrid(int width_cells, int height_cells, double resolution,
                             const thorvald_base::Pose2D& origin_pose, std::int8_t fill)
    : width(width_cells),
      height(height_cells),
      resolution_m(resolution),
      origin(origin_pose),
      data(static_cast<std::size_t>(width_cells) * static_cast<std::size_t>(height_cells), fill) {}

bool OccupancyGrid::worldToCell(const Eigen::Vector2d& p, int* cx, int* cy) const {
  const Eigen::Vector2d local = toGrid(p);
  const double c = std::floor(local.x() / resolution_m);
  const double r = std::floor(local.y() / resolution_m);
  if (!(c >= 0.0 && r >= 0.0 && c < width && r < height)) return false;
  *cx = static_cast<int>(c);
  *cy = static_cast<int>(r);
  return true;
}

std::int8_t OccupancyGrid::valueAt(const Eigen::Vector2d& p) const {
  int cx = 0, cy = 0;
  return worldToCell(p, &cx, &cy) ? at(cx, cy) : kUnknown;
}

std::string OccupancyGrid::check() const {
  if (!(resolution_m > 0.0) || !std::isfinite(resolution_m)) return "resolution must be > 0";
  if (!origin.finite()) return "origin must be finite";
  if (width <= 0 || height <= 0) return "width and height must be > 0";
  if (data.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height))
    return "data size " + std::to_string(data.size()) + " != width x height " +
           std::to_string(static_cast<long long>(width) * height);
  if (!surface.empty()) return surface.check(data.size());
  return {};
}

}  // namespace thorvald_map
