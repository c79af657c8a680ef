#pragma once

#include <cstdint>
#include <string>

#include "greenhouse_rail_nav/occupancy_map.h"

namespace greenhouse_rail_nav {

/// Reads a map the way map_server keeps it: a YAML file with `image` (PGM/PNG, relative to the YAML
/// file unless absolute), `resolution` [m/cell], `origin` [x, y, yaw], `negate`, `occupied_thresh`,
/// `free_thresh` and optionally `mode` (trinary, the default, or scale) and `wall_surface` (a file beside it where
/// thorvald_navigation's headland_mapper keeps the mean beam end of each cell, read into map->surface; only with an
/// unrotated origin). Returns false and says what is
/// wrong in *error (which file, which key, what was expected). An image whose header claims more than
/// max_cells pixels is refused before it is decoded, with the size in the message.
bool loadMapYaml(const std::string& yaml_path, OccupancyMap* map, std::string* error,
                 std::uint64_t max_cells = 200000000);

/// Width and height from a PGM (P2, P5) or PNG header without decoding the image; false for other formats
/// or a header that cannot be read.
bool readImageHeaderSize(const std::string& image_path, std::uint64_t* width, std::uint64_t* height);

/// Writes a map as map_server's map_saver would (trinary PGM + YAML next to it, image path relative).
bool saveMapYaml(const OccupancyMap& map, const std::string& yaml_path, std::string* error);

}  // namespace greenhouse_rail_nav
