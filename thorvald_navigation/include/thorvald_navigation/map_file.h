#pragma once

#include <string>

#include "thorvald_navigation/grid2d.h"

namespace thorvald_navigation {

/// Writes `grid` in map_server's format: `<stem>.pgm` (binary P5, 254 free, 0 occupied, 205 unknown; first row
/// of the image is the grid's top row) and `<stem>.yaml` (image, resolution, origin, negate 0, occupied_thresh
/// 0.65, free_thresh 0.196). Cells >= 65 are written occupied, <= 19 free, the rest unknown.
/// Returns an empty string on success, else what failed.
std::string saveMap(const Grid2D& grid, const std::string& stem);

/// Reads a map_server YAML (and the image it names, PGM P5/P2, relative to the YAML) in trinary mode.
/// Rotated origins are rejected. Returns an empty string on success, else what is wrong (file, key).
std::string loadMap(const std::string& yaml_path, Grid2D* grid);

}  // namespace thorvald_navigation
