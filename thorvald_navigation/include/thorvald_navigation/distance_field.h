#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "thorvald_map/occupancy_grid.h"
#include "thorvald_map/wall_surface.h"

namespace thorvald_navigation {

/// Euclidean distance from every cell centre to the nearest occupied cell centre of a grid, clamped at
/// `max_distance_m`, with bilinear interpolation and its gradient: the smooth likelihood field that scan
/// matching descends. Unknown cells count as free (they hold no wall).
///
/// With a thorvald_map::WallSurface (the mean beam end point of each cell), distances are measured instead to the
/// wall's surface where the beams ended: each wall cell (site) stands for a short line segment through the mean of the
/// end points in its 3x3 neighbourhood, along their principal direction, one cell long; the distance at a point is the
/// smallest to the segments of the sites nearest to its cell and its 8 neighbours (exact feature transform), so its
/// zero is at the surface wherever it lies inside a cell, not at cell centres. `line_half_length_m` sets how far a wall
/// cell's segment reaches either way (default half a cell); 0 makes it the whole line (a point-to-line distance),
/// so that a wall seen at a grazing angle, whose cells hold beam ends only here and there, has no bumps along its
/// length for scan matching to slide into: along a straight wall only its ends and corners fix a position.
class DistanceField {
 public:
  DistanceField() = default;
  /// `occupied_threshold`: cells with value >= it are walls [0..100]. `faces_only`: only wall cells with a
  /// known-free 4-neighbour count (the row that holds the face), so that a wall drawn two or three cells thick (beam
  /// noise, the mapper's own pose error) still has its zero at the face instead of a flat band that scan matching
  /// slides into; a grid without any free cell keeps every wall cell.
  /// `surface` (optional, same size as the grid): where the beams ended inside each cell.
  DistanceField(const thorvald_map::OccupancyGrid& grid, double max_distance_m, int occupied_threshold = 65,
                bool faces_only = false, const thorvald_map::WallSurface* surface = nullptr,
                double line_half_length_m = -1.0);

  bool empty() const { return width_ == 0; }
  double maxDistance() const { return max_distance_m_; }
  int occupiedCells() const { return occupied_cells_; }
  /// Brings the field up to date with `grid` (same geometry as at construction, `surface` as at construction)
  /// after the cells listed in `changed_cells` changed their value and the cells in `moved_cells` their surface
  /// (indices into the grid): only the distances within reach of a changed cell are recomputed, tile by tile, so a
  /// mapper's field costs what a scan changed rather than what the map holds. Equal to a field built anew from the
  /// same grid (tested).
  void update(const thorvald_map::OccupancyGrid& grid, const thorvald_map::WallSurface* surface,
              const std::vector<int>& changed_cells, const std::vector<int>& moved_cells);
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
  /// True when distances are measured to the walls' sub-cell surface.
  bool subCell() const { return sub_cell_; }

 private:
  /// A wall cell's piece of surface: a segment through `point` along `tangent`, `half_length` either way.
  struct Surfel {
    Eigen::Vector2f point = Eigen::Vector2f::Zero(), tangent = Eigen::Vector2f::UnitX();
    float half_length = 0.0f;
  };
  bool isSite(const thorvald_map::OccupancyGrid& grid, int x, int y) const;
  /// Exact transform of the sites in window [wx0, wx1] x [wy0, wy1] written to the cells of the box [bx0, bx1] x
  /// [by0, by1] inside it (exact there when the window reaches the box's cells' reach further on every side).
  void transformWindow(int wx0, int wy0, int wx1, int wy1, int bx0, int by0, int bx1, int by1);
  void computeSurfel(const thorvald_map::WallSurface& surface, int x, int y);
  double surfaceDistance(const Eigen::Vector2d& p, Eigen::Vector2d* gradient) const;

  int width_ = 0, height_ = 0, occupied_cells_ = 0;
  double resolution_m_ = 1.0, origin_x_m_ = 0.0, origin_y_m_ = 0.0, max_distance_m_ = 1.0;
  int occupied_threshold_ = 65;
  bool faces_ = false;               ///< sites are the face cells only
  bool sub_cell_ = false;            ///< distances to the surfels (a thorvald_map::WallSurface was given)
  int reach_cells_ = 1;              ///< max distance in cells, rounded up, plus one
  float line_half_length_m_ = 0.0f;  ///< reach of a line surfel either way [m] (infinite: the whole line)
  std::vector<float> dist_;
  std::vector<std::uint8_t> site_;  ///< per cell: is a site
  std::vector<int> site_of_;        ///< per cell: the nearest site's cell index (sub-cell mode), -1 none
  std::vector<Surfel> surfel_;      ///< per cell, valid where the cell is a site (sub-cell mode)
};

}  // namespace thorvald_navigation
