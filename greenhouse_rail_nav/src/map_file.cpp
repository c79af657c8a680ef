#include "greenhouse_rail_nav/map_file.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>

#include <opencv2/imgcodecs.hpp>
#include <yaml-cpp/yaml.h>

namespace greenhouse_rail_nav {
namespace {

std::string directoryOf(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string(".") : path.substr(0, slash);
}

std::string baseName(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
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

/// Next whitespace-separated token of a PNM header, skipping '#' comments.
bool pnmToken(std::istream& in, std::string* token) {
  token->clear();
  char c = 0;
  while (in.get(c)) {
    if (c == '#') {
      std::string comment;
      std::getline(in, comment);
    } else if (!std::isspace(static_cast<unsigned char>(c))) {
      token->push_back(c);
      break;
    }
  }
  while (in.get(c) && !std::isspace(static_cast<unsigned char>(c))) token->push_back(c);
  return !token->empty();
}

bool parseSize(const std::string& token, std::uint64_t* value) {
  if (token.empty() || token.size() > 19 || token.find_first_not_of("0123456789") != std::string::npos) return false;
  *value = std::stoull(token);
  return true;
}

/// Reads headland_mapper's wall surface file (a header line, `size W H`, then `cell_x cell_y mean_x mean_y hits` per
/// cell with beam ends; cells counted from the map's origin, means in the map frame) into map->surface.
bool loadCellSurface(const std::string& path, OccupancyMap* map, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = "cannot open wall surface '" + path + "'";
    return false;
  }
  std::string line, word;
  std::getline(in, line);
  if (line.rfind("#", 0) != 0 || line.find("wall surface") == std::string::npos) {
    *error = path + ": not a wall surface file (its first line must be the '# ... wall surface: ...' header)";
    return false;
  }
  long w = 0, h = 0;
  std::getline(in, line);
  std::istringstream size_line(line);
  if (!(size_line >> word >> w >> h) || word != "size" || w != map->width || h != map->height) {
    *error = path + ": line 2 must be 'size " + std::to_string(map->width) + " " + std::to_string(map->height) +
             "' (the map image's size)";
    return false;
  }
  CellSurface s;
  s.hits.assign(map->cells.size(), 0.0f);
  s.mean_m.assign(map->cells.size(), Eigen::Vector2f::Zero());
  const double res = map->resolution, slack = 1e-4;
  for (int n = 3; std::getline(in, line); ++n) {
    if (line.empty()) continue;
    std::istringstream ls(line);
    long c = 0, r = 0;
    double mx = 0.0, my = 0.0, hits = 0.0;
    if (!(ls >> c >> r >> mx >> my >> hits) || !map->inside(static_cast<int>(c), static_cast<int>(r)) ||
        !std::isfinite(mx) || !std::isfinite(my) || !(hits > 0.0 && hits < 1e9)) {
      *error = path + ":" + std::to_string(n) + ": expected 'cell_x cell_y mean_x mean_y hits' inside the map";
      return false;
    }
    const double x0 = map->origin.x + c * res, y0 = map->origin.y + r * res;
    if (mx < x0 - slack || mx > x0 + res + slack || my < y0 - slack || my > y0 + res + slack) {
      *error = path + ":" + std::to_string(n) + ": mean end point outside its cell";
      return false;
    }
    const std::size_t i = static_cast<std::size_t>(r) * map->width + c;
    s.mean_m[i] = Eigen::Vector2f(static_cast<float>(mx), static_cast<float>(my));
    s.hits[i] = static_cast<float>(hits);
  }
  map->surface = std::move(s);
  return true;
}

}  // namespace

bool readImageHeaderSize(const std::string& image_path, std::uint64_t* width, std::uint64_t* height) {
  std::ifstream in(image_path, std::ios::binary);
  if (!in) return false;
  char magic[8] = {};
  in.read(magic, 8);
  if (in.gcount() >= 2 && magic[0] == 'P' && (magic[1] == '2' || magic[1] == '5')) {
    in.clear();
    in.seekg(2);
    std::string w, h;
    return pnmToken(in, &w) && pnmToken(in, &h) && parseSize(w, width) && parseSize(h, height);
  }
  static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (in.gcount() == 8 && std::equal(magic, magic + 8, reinterpret_cast<const char*>(kPng))) {
    unsigned char ihdr[16] = {};
    in.read(reinterpret_cast<char*>(ihdr), 16);  // length, "IHDR", width, height (big-endian)
    if (in.gcount() != 16) return false;
    auto be32 = [](const unsigned char* b) {
      return (std::uint64_t{b[0]} << 24) | (std::uint64_t{b[1]} << 16) | (std::uint64_t{b[2]} << 8) | b[3];
    };
    *width = be32(ihdr + 8);
    *height = be32(ihdr + 12);
    return true;
  }
  return false;
}

bool loadMapYaml(const std::string& yaml_path, OccupancyMap* map, std::string* error, std::uint64_t max_cells) {
  YAML::Node doc;
  try {
    doc = YAML::LoadFile(yaml_path);
  } catch (const YAML::Exception& e) {
    *error = yaml_path + ": cannot read map YAML: " + e.what();
    return false;
  }
  std::string image;
  double resolution = 0.0, occupied_thresh = 0.65, free_thresh = 0.196;
  int negate = 0;
  std::vector<double> origin;
  if (!readKey(doc, "image", yaml_path, "an image file name", &image, error) ||
      !readKey(doc, "resolution", yaml_path, "a cell size in metres", &resolution, error) ||
      !readKey(doc, "origin", yaml_path, "[x, y, yaw]", &origin, error) ||
      !readKey(doc, "negate", yaml_path, "0 or 1", &negate, error) ||
      !readKey(doc, "occupied_thresh", yaml_path, "a number in (0, 1]", &occupied_thresh, error) ||
      !readKey(doc, "free_thresh", yaml_path, "a number in [0, 1)", &free_thresh, error)) {
    return false;
  }
  std::string mode = "trinary";
  try {
    if (doc["mode"]) mode = doc["mode"].as<std::string>();
  } catch (const YAML::Exception&) {
    *error = yaml_path + ": 'mode' must be trinary or scale";
    return false;
  }
  if (!(resolution > 0.0) || !std::isfinite(resolution)) {
    *error = yaml_path + ": 'resolution' must be > 0, got " + std::to_string(resolution);
    return false;
  }
  if (origin.size() != 3) {
    *error = yaml_path + ": 'origin' must be [x, y, yaw], got " + std::to_string(origin.size()) + " numbers";
    return false;
  }
  if (!(free_thresh >= 0.0 && free_thresh < occupied_thresh && occupied_thresh <= 1.0)) {
    *error = yaml_path + ": need 0 <= free_thresh < occupied_thresh <= 1";
    return false;
  }
  if (mode != "trinary" && mode != "scale") {
    *error = yaml_path + ": 'mode' must be trinary or scale, got '" + mode + "'";
    return false;
  }
  const std::string image_path = (!image.empty() && image[0] == '/') ? image : directoryOf(yaml_path) + "/" + image;
  std::uint64_t header_w = 0, header_h = 0;
  if (readImageHeaderSize(image_path, &header_w, &header_h) &&
      (header_w == 0 || header_h == 0 || header_w * header_h > max_cells)) {
    *error = yaml_path + ": image '" + image_path + "' claims " + std::to_string(header_w) + " x " +
             std::to_string(header_h) + " pixels; the limit is " + std::to_string(max_cells) + " cells";
    return false;
  }
  cv::Mat img;
  try {
    img = cv::imread(image_path, cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception& e) {
    *error = yaml_path + ": cannot decode image '" + image_path + "': " + e.what();
    return false;
  }
  if (!img.empty() && static_cast<std::uint64_t>(img.cols) * img.rows > max_cells) {
    *error = yaml_path + ": image '" + image_path + "' has " + std::to_string(img.cols) + " x " +
             std::to_string(img.rows) + " pixels; the limit is " + std::to_string(max_cells) + " cells";
    return false;
  }
  if (img.empty()) {
    *error = yaml_path + ": cannot read image '" + image_path + "'";
    return false;
  }
  *map = OccupancyMap(img.cols, img.rows, resolution, Pose2D(origin[0], origin[1], origin[2]));
  for (int r = 0; r < img.rows; ++r) {
    for (int c = 0; c < img.cols; ++c) {
      const double pixel = img.at<std::uint8_t>(r, c);
      const double occ = negate ? pixel / 255.0 : (255.0 - pixel) / 255.0;
      std::int8_t value = OccupancyMap::kUnknown;
      if (occ > occupied_thresh) {
        value = OccupancyMap::kOccupied;
      } else if (occ < free_thresh) {
        value = OccupancyMap::kFree;
      } else if (mode == "scale") {
        value = static_cast<std::int8_t>(std::lround(99.0 * (occ - free_thresh) / (occupied_thresh - free_thresh)));
      }
      map->at(c, img.rows - 1 - r) = value;  // image row 0 is the top of the map
    }
  }
  std::string surface_file;
  try {
    if (doc["wall_surface"]) surface_file = doc["wall_surface"].as<std::string>();
  } catch (const YAML::Exception&) {
    *error = yaml_path + ": 'wall_surface' must be a file name";
    return false;
  }
  if (!surface_file.empty()) {
    if (origin[2] != 0.0) {
      *error = yaml_path + ": 'wall_surface' needs an unrotated origin (yaw 0), got yaw " + std::to_string(origin[2]);
      return false;
    }
    const std::string path = surface_file[0] == '/' ? surface_file : directoryOf(yaml_path) + "/" + surface_file;
    if (!loadCellSurface(path, map, error)) {
      *error = yaml_path + ": " + *error;
      return false;
    }
  }
  return true;
}

bool saveMapYaml(const OccupancyMap& map, const std::string& yaml_path, std::string* error) {
  std::string stem = yaml_path;
  if (stem.size() > 5 && stem.substr(stem.size() - 5) == ".yaml") stem.resize(stem.size() - 5);
  const std::string pgm_path = stem + ".pgm";
  cv::Mat img(map.height, map.width, CV_8UC1);
  for (int r = 0; r < map.height; ++r) {
    for (int c = 0; c < map.width; ++c) {
      const std::int8_t v = map.at(c, map.height - 1 - r);
      img.at<std::uint8_t>(r, c) = v < 0 ? 205 : (v >= 65 ? 0 : (v <= 19 ? 254 : 205));
    }
  }
  if (!cv::imwrite(pgm_path, img)) {
    *error = "cannot write " + pgm_path;
    return false;
  }
  std::ofstream out(yaml_path);
  if (!out) {
    *error = "cannot write " + yaml_path;
    return false;
  }
  out.precision(10);
  out << "image: " << baseName(pgm_path) << "\nresolution: " << map.resolution << "\norigin: [" << map.origin.x << ", "
      << map.origin.y << ", " << map.origin.yaw << "]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
  return static_cast<bool>(out);
}

}  // namespace greenhouse_rail_nav
