#pragma once

#include <string>

#include "thorvald_navigation/grid2d.h"
#include "thorvald_navigation/wall_surface.h"

namespace thorvald_navigation {

/// Writes `grid` in map_server's format: `<stem>.pgm` (binary P5, 254 free, 0 occupied, 205 unknown; first row
/// of the image is the grid's top row) and `<stem>.yaml` (image, resolution, origin, negate 0, occupied_thresh
/// 0.65, free_thresh 0.196). Cells >= 65 are written occupied, <= 19 free, the rest unknown.
/// `surface` (optional, same size as the grid): also writes `<stem>.surface` (text: a header line, `size W H`, then
/// `cell_x cell_y mean_x mean_y hits` for every cell with beam ends) and names it in the YAML under `wall_surface`
/// (map_server ignores the key). Returns an empty string on success, else what failed.
std::string saveMap(const Grid2D& grid, const std::string& stem, const WallSurface* surface = nullptr);

/// Reads a map_server YAML (and the image it names, PGM P5/P2, relative to the YAML) in trinary mode.
/// Rotated origins are rejected. `surface` (optional): filled from the YAML's `wall_surface` file when it names one
/// (else left empty); every mean must lie inside its cell. Returns an empty string on success, else what is wrong
/// (file, key, line).
std::string loadMap(const std::string& yaml_path, Grid2D* grid, WallSurface* surface = nullptr);

}  // namespace thorvald_navigation
