#include "thorvald_map/map_file.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "image_io.h"

namespace thorvald_map {
namespace {

constexpr const char* kSurfaceHeader = "# thorvald_navigation wall surface: cell_x cell_y mean_x mean_y hits";

std::string directoryOf(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

std::string baseName(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

std::string besideYaml(const std::string& yaml_path, const std::string& file) {
  return (!file.empty() && file[0] == '/') ? file : directoryOf(yaml_path) + file;
}

template <typename T>
bool readKey(const YAML::Node& node, const std::string& key, const std::string& file, const std::string& expected,
             T* value, std::string* error) {
  if (!node[key]) {
    *error = file + ": missing key '" + key + "' (expected " + expected + ")";
    return false;
  }
  try {
    *value = node[key].as<T>();
  } catch (const YAML::Exception&) {
    *error = file + ": key '" + key + "' is not " + expected;
    return false;
  }
  return true;
}

/// The keys of a map YAML other than the image.
struct MapYaml {
  std::string image, mode = "trinary", wall_surface;
  double resolution = 0.0, occupied_thresh = 0.65, free_thresh = 0.196;
  int negate = 0;
  std::vector<double> origin;
};

bool readMapYaml(const std::string& path, const MapLoadOptions& options, MapYaml* m, std::string* error) {
  YAML::Node doc;
  try {
    doc = YAML::LoadFile(path);
  } catch (const YAML::Exception& e) {
    *error = path + ": cannot read map YAML: " + e.what();
    return false;
  }
  if (!readKey(doc, "image", path, "an image file name", &m->image, error) ||
      !readKey(doc, "resolution", path, "a cell size in metres", &m->resolution, error) ||
      !readKey(doc, "origin", path, "[x, y, yaw]", &m->origin, error) ||
      !readKey(doc, "negate", path, "0 or 1", &m->negate, error) ||
      !readKey(doc, "occupied_thresh", path, "a number in (0, 1]", &m->occupied_thresh, error) ||
      !readKey(doc, "free_thresh", path, "a number in [0, 1)", &m->free_thresh, error) ||
      (doc["mode"] && !readKey(doc, "mode", path, "trinary or scale", &m->mode, error)) ||
      (doc["wall_surface"] && !readKey(doc, "wall_surface", path, "a file name", &m->wall_surface, error)))
    return false;
  if (!(m->resolution > 0.0) || !std::isfinite(m->resolution)) {
    *error = path + ": 'resolution' must be > 0, got " + std::to_string(m->resolution);
  } else if (m->origin.size() != 3) {
    *error = path + ": 'origin' must be [x, y, yaw], got " + std::to_string(m->origin.size()) + " numbers";
  } else if (!std::isfinite(m->origin[0]) || !std::isfinite(m->origin[1]) || !std::isfinite(m->origin[2])) {
    *error = path + ": 'origin' must be finite";
  } else if (m->origin[2] != 0.0 && !options.allow_rotated_origin) {
    *error = path + ": 'origin' is rotated (yaw " + std::to_string(m->origin[2]) + "); rotated map origins are not " +
             "supported here, expected yaw 0";
  } else if (!(m->free_thresh >= 0.0 && m->free_thresh < m->occupied_thresh && m->occupied_thresh <= 1.0)) {
    *error = path + ": need 0 <= free_thresh < occupied_thresh <= 1";
  } else if (m->mode != "trinary" && m->mode != "scale") {
    *error = path + ": 'mode' must be trinary or scale, got '" + m->mode + "'";
  } else if (!m->wall_surface.empty() && m->origin[2] != 0.0) {
    *error = path + ": 'wall_surface' needs an unrotated origin (yaw 0), got yaw " + std::to_string(m->origin[2]);
  } else {
    return true;
  }
  return false;
}

/// map_server's reading of a pixel: darkness is occupancy.
std::int8_t occupancyOf(int pixel, int max_value, const MapYaml& m) {
  const double occ =
      m.negate ? static_cast<double>(pixel) / max_value : static_cast<double>(max_value - pixel) / max_value;
  if (occ > m.occupied_thresh) return kOccupied;
  if (occ < m.free_thresh) return kFree;
  if (m.mode == "scale")
    return static_cast<std::int8_t>(std::lround(99.0 * (occ - m.free_thresh) / (m.occupied_thresh - m.free_thresh)));
  return kUnknown;
}

/// Reads the mapper's wall surface file into grid->surface (the grid's size and origin must be set).
bool loadSurface(const std::string& path, OccupancyGrid* grid, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = "cannot open wall surface '" + path + "'";
    return false;
  }
  std::string line, word;
  std::getline(in, line);
  if (line != kSurfaceHeader) {
    *error = path + ":1: not a wall surface file (the first line must be the header '" + kSurfaceHeader + "')";
    return false;
  }
  long w = 0, h = 0;
  std::getline(in, line);
  std::istringstream size_line(line);
  if (!(size_line >> word >> w >> h) || word != "size" || w != grid->width || h != grid->height) {
    *error = path + ":2: must be 'size " + std::to_string(grid->width) + " " + std::to_string(grid->height) +
             "' (the map image's size)";
    return false;
  }
  WallSurface s;
  s.hits.assign(grid->data.size(), 0.0f);
  s.mean_m.assign(grid->data.size(), Eigen::Vector2f::Zero());
  const double res = grid->resolution_m, slack = 1e-4;
  for (int n = 3; std::getline(in, line); ++n) {
    if (line.empty()) continue;
    std::istringstream ls(line);
    long x = 0, y = 0;
    double mx = 0.0, my = 0.0, hits = 0.0;
    if (!(ls >> x >> y >> mx >> my >> hits) || !grid->inside(static_cast<int>(x), static_cast<int>(y)) ||
        !std::isfinite(mx) || !std::isfinite(my) || !(hits > 0.0 && hits < 1e9)) {
      *error = path + ":" + std::to_string(n) + ": expected 'cell_x cell_y mean_x mean_y hits' inside the map";
      return false;
    }
    const double x0 = grid->origin.x + x * res, y0 = grid->origin.y + y * res;
    if (mx < x0 - slack || mx > x0 + res + slack || my < y0 - slack || my > y0 + res + slack) {
      *error = path + ":" + std::to_string(n) + ": mean end point outside its cell";
      return false;
    }
    const std::size_t i = grid->index(static_cast<int>(x), static_cast<int>(y));
    s.mean_m[i] = Eigen::Vector2f(static_cast<float>(mx), static_cast<float>(my));
    s.hits[i] = static_cast<float>(hits);
  }
  grid->surface = std::move(s);
  return true;
}

bool saveSurface(const OccupancyGrid& grid, const std::string& path, std::string* error) {
  std::ofstream out(path);
  if (!out) {
    *error = "cannot write " + path;
    return false;
  }
  out.precision(9);
  out << kSurfaceHeader << "\nsize " << grid.width << " " << grid.height << "\n";
  for (int y = 0; y < grid.height; ++y)
    for (int x = 0; x < grid.width; ++x) {
      const std::size_t i = grid.index(x, y);
      if (grid.surface.hits[i] > 0.0f)
        out << x << " " << y << " " << grid.surface.mean_m[i].x() << " " << grid.surface.mean_m[i].y() << " "
            << grid.surface.hits[i] << "\n";
    }
  if (!out) {
    *error = "write failed: " + path;
    return false;
  }
  return true;
}

}  // namespace

bool loadMap(const std::string& yaml_path, OccupancyGrid* grid, std::string* error, const MapLoadOptions& options) {
  MapYaml m;
  if (!readMapYaml(yaml_path, options, &m, error)) return false;
  GreyImage img;
  if (!readGreyImage(besideYaml(yaml_path, m.image), options.max_cells, &img, error)) {
    *error = yaml_path + ": " + *error;
    return false;
  }
  OccupancyGrid g(img.width, img.height, m.resolution, thorvald_base::Pose2D(m.origin[0], m.origin[1], m.origin[2]));
  for (int r = 0; r < img.height; ++r)
    for (int c = 0; c < img.width; ++c)  // image row 0 is the top of the map
      g.at(c, img.height - 1 - r) =
          occupancyOf(img.pixels[static_cast<std::size_t>(r) * img.width + c], img.max_value, m);
  if (!m.wall_surface.empty() && !loadSurface(besideYaml(yaml_path, m.wall_surface), &g, error)) {
    *error = yaml_path + ": " + *error;
    return false;
  }
  *grid = std::move(g);
  return true;
}

bool saveMap(const OccupancyGrid& grid, const std::string& path, std::string* error) {
  const std::string problem = grid.check();
  if (!problem.empty()) {
    *error = "cannot save map: " + problem;
    return false;
  }
  if (!grid.surface.empty() && grid.origin.yaw != 0.0) {
    *error = "cannot save map: a wall surface needs an unrotated origin (yaw 0)";
    return false;
  }
  std::string stem = path;
  if (stem.size() > 5 && stem.compare(stem.size() - 5, 5, ".yaml") == 0) stem.resize(stem.size() - 5);
  GreyImage img;
  img.width = grid.width;
  img.height = grid.height;
  img.pixels.resize(grid.data.size());
  for (int r = 0; r < grid.height; ++r)
    for (int c = 0; c < grid.width; ++c) {
      const int v = grid.at(c, grid.height - 1 - r);
      img.pixels[static_cast<std::size_t>(r) * grid.width + c] = v < 0 ? 205 : (v >= 65 ? 0 : (v <= 19 ? 254 : 205));
    }
  if (!writePgm(stem + ".pgm", img, error)) return false;
  if (!grid.surface.empty() && !saveSurface(grid, stem + ".surface", error)) return false;
  const std::string yaml_path = stem + ".yaml";
  std::ofstream out(yaml_path);
  if (!out) {
    *error = "cannot write " + yaml_path;
    return false;
  }
  out.precision(10);
  out << "image: " << baseName(stem) << ".pgm\nresolution: " << grid.resolution_m << "\norigin: [" << grid.origin.x
      << ", " << grid.origin.y << ", " << grid.origin.yaw
      << "]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
  if (!grid.surface.empty()) out << "wall_surface: " << baseName(stem) << ".surface\n";
  if (!out) {
    *error = "write failed: " + yaml_path;
    return false;
  }
  return true;
}

}  // namespace thorvald_map
