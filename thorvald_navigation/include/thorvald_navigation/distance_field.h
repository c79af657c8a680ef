#pragma once

#include <vector>

#include <Eigen/Core>

#include "thorvald_navigation/grid2d.h"

namespace thorvald_navigation {

/// Euclidean distance from every cell centre to the nearest occupied cell centre of a grid, clamped at
/// `max_distance_m`, with bilinear interpolation and its gradient: the smooth likelihood field that scan
/// matching descends. Unknown cells count as free (they hold no wall).
class DistanceField {
 public:
  DistanceField() = default;
  /// `occupied_threshold`: cells with value >= it are walls [0..100]. `faces_only`: only wall cells with a
  /// known-free 4-neighbour count (the row that holds the face), so that a wall drawn two or three cells thick (beam
  /// noise, the mapper's own pose error) still has its zero at the face instead of a flat band that scan matching
  /// slides into; a grid without any free cell keeps every wall cell.
  DistanceField(const Grid2D& grid, double max_distance_m, int occupied_threshold = 65, bool faces_only = false);

  bool empty() const { return width_ == 0; }
  double maxDistance() const { return max_distance_m_; }
  int occupiedCells() const { return occupied_cells_; }
  /// Distance [m] at a world point (max distance outside the grid). `gradient` (optional) in [m/m].
  double distance(const Eigen::Vector2d& p, Eigen::Vector2d* gradient = nullptr) const;
  /// Distance at a cell, no interpolation [m]; max distance outside.
  double cellDistance(int cx, int cy) const {
    if (cx < 0 || cy < 0 || cx >= width_ || cy >= height_) return max_distance_m_;
    return dist_[static_cast<std::size_t>(cy) * width_ + cx];
  }
  double resolution() const { return resolution_m_; }
  double originX() const { return origin_x_m_; }
  double originY() const { return origin_y_m_; }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  int width_ = 0, height_ = 0, occupied_cells_ = 0;
  double resolution_m_ = 1.0, origin_x_m_ = 0.0, origin_y_m_ = 0.0, max_distance_m_ = 1.0;
  std::vector<float> dist_;
};

}  // namespace thorvald_navigation
