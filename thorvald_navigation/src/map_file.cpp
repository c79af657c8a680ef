#include "thorvald_navigation/map_file.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include <yaml-cpp/yaml.h>

namespace thorvald_navigation {
namespace {

constexpr int kMaxSide = 20000;  // bounds what a map file may make us allocate

std::string baseName(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

std::string directoryOf(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

// Skips whitespace and '#' comments between PGM header fields.
bool readPgmNumber(std::istream& in, long* value) {
  for (;;) {
    const int c = in.peek();
    if (c == '#') {
      std::string line;
      std::getline(in, line);
    } else if (std::isspace(c)) {
      in.get();
    } else {
      break;
    }
  }
  return static_cast<bool>(in >> *value);
}

constexpr const char* kSurfaceHeader = "# thorvald_navigation wall surface: cell_x cell_y mean_x mean_y hits";

std::string saveSurface(const Grid2D& grid, const WallSurface& surface, const std::string& path) {
  const std::string bad = surface.check(grid.data.size());
  if (!bad.empty()) return "cannot save wall surface: " + bad;
  std::ofstream out(path);
  if (!out) return "cannot write " + path;
  out.precision(9);
  out << kSurfaceHeader << "\nsize " << grid.width << " " << grid.height << "\n";
  for (int y = 0; y < grid.height; ++y)
    for (int x = 0; x < grid.width; ++x) {
      const std::size_t i = grid.index(x, y);
      if (surface.hits[i] > 0.0f)
        out << x << " " << y << " " << surface.mean_m[i].x() << " " << surface.mean_m[i].y() << " " << surface.hits[i]
            << "\n";
    }
  if (!out) return "write failed: " + path;
  return {};
}

std::string loadSurface(const Grid2D& grid, const std::string& path, WallSurface* surface) {
  std::ifstream in(path);
  if (!in) return "cannot open wall surface " + path;
  std::string line, word;
  long w = 0, h = 0;
  std::getline(in, line);
  if (line != kSurfaceHeader) return path + ": not a wall surface file (header)";
  std::getline(in, line);
  std::istringstream size_line(line);
  if (!(size_line >> word >> w >> h) || word != "size" || w != grid.width || h != grid.height)
    return path + ": line 2 must be 'size " + std::to_string(grid.width) + " " + std::to_string(grid.height) + "'";
  WallSurface s;
  s.hits.assign(grid.data.size(), 0.0f);
  s.mean_m.assign(grid.data.size(), Eigen::Vector2f::Zero());
  const double res = grid.resolution_m, slack = 1e-4;
  for (int n = 3; std::getline(in, line); ++n) {
    if (line.empty()) continue;
    std::istringstream ls(line);
    long x = 0, y = 0;
    double mx = 0.0, my = 0.0, hits = 0.0;
    if (!(ls >> x >> y >> mx >> my >> hits) || !grid.inside(static_cast<int>(x), static_cast<int>(y)) ||
        !std::isfinite(mx) || !std::isfinite(my) || !(hits > 0.0 && hits < 1e9))
      return path + ":" + std::to_string(n) + ": expected 'cell_x cell_y mean_x mean_y hits' inside the map";
    const double x0 = grid.origin_x_m + x * res, y0 = grid.origin_y_m + y * res;
    if (mx < x0 - slack || mx > x0 + res + slack || my < y0 - slack || my > y0 + res + slack)
      return path + ":" + std::to_string(n) + ": mean end point outside its cell";
    const std::size_t i = grid.index(static_cast<int>(x), static_cast<int>(y));
    s.mean_m[i] = Eigen::Vector2f(static_cast<float>(mx), static_cast<float>(my));
    s.hits[i] = static_cast<float>(hits);
  }
  *surface = std::move(s);
  return {};
}

}  // namespace

std::string saveMap(const Grid2D& grid, const std::string& stem, const WallSurface* surface) {
  const std::string problem = grid.check();
  if (!problem.empty()) return "cannot save map: " + problem;
  const std::string pgm_path = stem + ".pgm";
  std::ofstream pgm(pgm_path, std::ios::binary);
  if (!pgm) return "cannot write " + pgm_path;
  pgm << "P5\n# thorvald_navigation map\n" << grid.width << " " << grid.height << "\n255\n";
  std::string row(static_cast<std::size_t>(grid.width), '\0');
  for (int y = grid.height - 1; y >= 0; --y) {
    for (int x = 0; x < grid.width; ++x) {
      const int v = grid.at(x, y);
      row[static_cast<std::size_t>(x)] = static_cast<char>(v < 0 ? 205 : (v >= 65 ? 0 : (v <= 19 ? 254 : 205)));
    }
    pgm.write(row.data(), static_cast<std::streamsize>(row.size()));
  }
  if (!pgm) return "write failed: " + pgm_path;
  const std::string yaml_path = stem + ".yaml";
  std::ofstream yaml(yaml_path);
  if (!yaml) return "cannot write " + yaml_path;
  yaml.precision(9);
  yaml << "image: " << baseName(pgm_path) << "\nresolution: " << grid.resolution_m << "\norigin: [" << grid.origin_x_m
       << ", " << grid.origin_y_m << ", 0.0]\nnegate: 0\noccupied_thresh: 0.65\n"
       << "free_thresh: 0.196\n";
  if (surface) {
    const std::string e = saveSurface(grid, *surface, stem + ".surface");
    if (!e.empty()) return e;
    yaml << "wall_surface: " << baseName(stem + ".surface") << "\n";
  }
  if (!yaml) return "write failed: " + yaml_path;
  return {};
}

std::string loadMap(const std::string& yaml_path, Grid2D* grid, WallSurface* surface) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(yaml_path);
  } catch (const std::exception& e) {
    return yaml_path + ": cannot read YAML: " + e.what();
  }
  std::string image, surface_file;
  double resolution = 0.0, occ = 0.65, free_t = 0.196;
  int negate = 0;
  std::vector<double> origin;
  try {
    if (!root["image"] || !root["resolution"] || !root["origin"])
      return yaml_path + ": needs keys image, resolution and origin";
    image = root["image"].as<std::string>();
    resolution = root["resolution"].as<double>();
    origin = root["origin"].as<std::vector<double>>();
    if (root["negate"]) negate = root["negate"].as<int>();
    if (root["occupied_thresh"]) occ = root["occupied_thresh"].as<double>();
    if (root["free_thresh"]) free_t = root["free_thresh"].as<double>();
    if (root["wall_surface"]) surface_file = root["wall_surface"].as<std::string>();
    if (root["mode"] && root["mode"].as<std::string>() != "trinary")
      return yaml_path + ": only mode 'trinary' is supported, got '" + root["mode"].as<std::string>() + "'";
  } catch (const std::exception& e) {
    return yaml_path + ": bad value type: " + e.what();
  }
  if (!(resolution > 0.0) || !std::isfinite(resolution)) return yaml_path + ": resolution must be > 0";
  if (origin.size() != 3 || !std::isfinite(origin[0]) || !std::isfinite(origin[1]))
    return yaml_path + ": origin must be [x, y, yaw]";
  if (std::abs(origin[2]) > 1e-9) return yaml_path + ": rotated map origins (yaw != 0) are not supported";
  if (!(free_t < occ)) return yaml_path + ": free_thresh must be < occupied_thresh";
  const std::string image_path = (!image.empty() && image[0] == '/') ? image : directoryOf(yaml_path) + image;
  std::ifstream in(image_path, std::ios::binary);
  if (!in) return yaml_path + ": cannot open image " + image_path;
  std::string magic;
  in >> magic;
  long w = 0, h = 0, maxval = 0;
  if ((magic != "P5" && magic != "P2") || !readPgmNumber(in, &w) || !readPgmNumber(in, &h) ||
      !readPgmNumber(in, &maxval))
    return image_path + ": not a PGM (P5 or P2) image";
  if (w <= 0 || h <= 0 || w > kMaxSide || h > kMaxSide || maxval <= 0 || maxval > 255)
    return image_path + ": unsupported size " + std::to_string(w) + "x" + std::to_string(h) + " or maxval";
  in.get();  // the single whitespace after maxval
  Grid2D g(static_cast<int>(w), static_cast<int>(h), resolution, origin[0], origin[1]);
  for (long row = 0; row < h; ++row) {
    for (long col = 0; col < w; ++col) {
      long v = 0;
      if (magic == "P5") {
        const int c = in.get();
        if (c == EOF) return image_path + ": image data ends early";
        v = c;
      } else if (!readPgmNumber(in, &v)) {
        return image_path + ": image data ends early";
      }
      double p = static_cast<double>(maxval - v) / maxval;  // darkness = occupancy
      if (negate) p = 1.0 - p;
      g.at(static_cast<int>(col), static_cast<int>(h - 1 - row)) =
          p > occ ? kOccupied : (p < free_t ? kFree : kUnknown);
    }
  }
  if (surface) {
    *surface = WallSurface{};
    if (!surface_file.empty()) {
      const std::string path = surface_file[0] == '/' ? surface_file : directoryOf(yaml_path) + surface_file;
      const std::string e = loadSurface(g, path, surface);
      if (!e.empty()) return yaml_path + ": " + e;
    }
  }
  *grid = std::move(g);
  return {};
}

}  // namespace thorvald_navigation
