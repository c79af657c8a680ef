#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace thorvald_map {

/// Where the beams that ended in each cell of a grid ended: per cell the mean end point and their number. An
/// occupancy grid says which cell holds a wall, not where inside the cell its face is; this keeps that, so that a wall
/// whose face is anywhere inside a cell is matched (and analysed) where it is, not at the cell's centre (up to half a
/// cell off). Same size and cell order as the grid it belongs to, or empty.
struct WallSurface {
  std::vector<Eigen::Vector2f> mean_m;  ///< mean beam end point in the grid's parent frame [m]; unused where hits is 0
  std::vector<float> hits;              ///< beam ends counted in the cell (0: none)

  bool empty() const { return hits.empty(); }
  std::size_t size() const { return hits.size(); }
  /// Empty string when it fits a grid of `cells` cells, else what is wrong.
  std::string check(std::size_t cells) const;
};

}  // namespace thorvald_map
