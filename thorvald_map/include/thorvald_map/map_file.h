#pragma once

#include <cstdint>
#include <string>

#include "thorvald_map/occupancy_grid.h"

namespace thorvald_map {

/// What a map file may be.
struct MapLoadOptions {
  /// An image whose header claims more pixels than this is refused before it is decoded [cells].
  std::uint64_t max_cells = 200000000;
  /// false: a map whose origin has a yaw is refused (for code that works on unrotated grids).
  bool allow_rotated_origin = true;
};

/// Reads a map the way map_server keeps it: a YAML file with `image` (PGM P2/P5 or any image OpenCV reads, relative
/// to the YAML file unless absolute), `resolution` [m/cell], `origin` [x, y, yaw], `negate`, `occupied_thresh`,
/// `free_thresh`, optionally `mode` (trinary, the default, or scale) and `wall_surface`: the file beside it where the
/// mapper keeps the mean beam end of each cell (read into grid->surface; only with an unrotated origin). The surface
/// file is a header line, `size W H`, then `cell_x cell_y mean_x mean_y hits` per cell with beam ends, every mean
/// inside its cell. Returns false and says what is wrong in *error (which file, which key or line, what was expected).
bool loadMap(const std::string& yaml_path, OccupancyGrid* grid, std::string* error,
             const MapLoadOptions& options = MapLoadOptions());

/// Writes a map as map_server's map_saver would: `<stem>.pgm` (binary P5, 254 free, 0 occupied, 205 unknown; the
/// image's first row is the grid's top row; values >= 65 occupied, <= 19 free, the rest unknown) and `<stem>.yaml`
/// (image path relative), and with a non-empty grid.surface also `<stem>.surface`, named by the YAML's `wall_surface`
/// key (map_server ignores it). `path` is the YAML file's path or the stem (a trailing ".yaml" is taken off).
bool saveMap(const OccupancyGrid& grid, const std::string& path, std::string* error);

/// Width and height from a PGM (P2, P5) or PNG header without decoding the image; false for other formats or a
/// header that cannot be read.
bool readImageHeaderSize(const std::string& image_path, std::uint64_t* width, std::uint64_t* height);

}  // namespace thorvald_map
