#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace thorvald_map {

/// A grey image as read from a map file: row 0 is the image's top row.
struct GreyImage {
  int width = 0;
  int height = 0;
  int max_value = 255;                ///< the value of white
  std::vector<std::uint16_t> pixels;  ///< width x height, row-major
};

/// Reads a PGM (P2 or P5, maxval up to 255) itself, any other format through OpenCV (8-bit grey). `max_cells` bounds
/// what the header may make it allocate. Returns false with what is wrong (naming `path`).
bool readGreyImage(const std::string& path, std::uint64_t max_cells, GreyImage* image, std::string* error);

/// Writes a binary P5 PGM (maxval 255). Returns false with what failed.
bool writePgm(const std::string& path, const GreyImage& image, std::string* error);

}  // namespace thorvald_map
