#pragma once

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace thorvald_navigation {

/// Occupancy values as nav_msgs/OccupancyGrid writes them.
constexpr std::int8_t kUnknown = -1;
constexpr std::int8_t kFree = 0;
constexpr std::int8_t kOccupied = 100;

/// A row-major occupancy grid: cell (0, 0) has its lower-left corner at `origin_x_m, origin_y_m` (no rotation),
/// rows go along +y. Values: -1 unknown, 0 free .. 100 occupied.
struct Grid2D {
  double resolution_m = 0.05;
  double origin_x_m = 0.0;
  double origin_y_m = 0.0;
  int width = 0;
  int height = 0;
  std::vector<std::int8_t> data;

  Grid2D() = default;
  Grid2D(int w, int h, double res, double ox, double oy, std::int8_t fill = kUnknown)
      : resolution_m(res),
        origin_x_m(ox),
        origin_y_m(oy),
        width(w),
        height(h),
        data(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), fill) {}

  bool inside(int cx, int cy) const { return cx >= 0 && cy >= 0 && cx < width && cy < height; }
  std::size_t index(int cx, int cy) const {
    return static_cast<std::size_t>(cy) * static_cast<std::size_t>(width) + static_cast<std::size_t>(cx);
  }
  std::int8_t at(int cx, int cy) const { return data[index(cx, cy)]; }
  std::int8_t& at(int cx, int cy) { return data[index(cx, cy)]; }
  /// Cell holding a world point (may be outside the grid).
  Eigen::Vector2i cellOf(const Eigen::Vector2d& p) const {
    return {static_cast<int>(std::floor((p.x() - origin_x_m) / resolution_m)),
            static_cast<int>(std::floor((p.y() - origin_y_m) / resolution_m))};
  }
  Eigen::Vector2d centerOf(int cx, int cy) const {
    return {origin_x_m + (cx + 0.5) * resolution_m, origin_y_m + (cy + 0.5) * resolution_m};
  }
  /// Empty string when the grid is usable, else what is wrong with it.
  std::string check() const {
    if (!(resolution_m > 0.0) || !std::isfinite(resolution_m)) return "resolution must be > 0";
    if (!std::isfinite(origin_x_m) || !std::isfinite(origin_y_m)) return "origin must be finite";
    if (width <= 0 || height <= 0) return "width and height must be > 0";
    if (data.size() != static_cast<std::size_t>(width) * static_cast<std::size_t>(height))
      return "data size " + std::to_string(data.size()) + " != width x height " +
             std::to_string(static_cast<long long>(width) * height);
    return {};
  }
};

}  // namespace thorvald_navigation
