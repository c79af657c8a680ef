#include "image_io.h"

#include <algorithm>
#include <cctype>
#include <fstream>

#include <opencv2/imgcodecs.hpp>

#include "thorvald_map/map_file.h"

namespace thorvald_map {
namespace {

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

std::string sizeRefusal(const std::string& path, std::uint64_t w, std::uint64_t h, std::uint64_t max_cells) {
  return "image '" + path + "' claims " + std::to_string(w) + " x " + std::to_string(h) + " pixels; the limit is " +
         std::to_string(max_cells) + " cells";
}

bool readPgm(const std::string& path, std::ifstream& in, std::uint64_t max_cells, GreyImage* image,
             std::string* error) {
  std::string magic, w_token, h_token, max_token;
  std::uint64_t w = 0, h = 0, maxval = 0;
  if (!pnmToken(in, &magic) || !pnmToken(in, &w_token) || !pnmToken(in, &h_token) || !pnmToken(in, &max_token) ||
      !parseSize(w_token, &w) || !parseSize(h_token, &h) || !parseSize(max_token, &maxval)) {
    *error = "image '" + path + "': not a PGM (P5 or P2) header";
    return false;
  }
  if (w == 0 || h == 0 || w > max_cells || h > max_cells || w * h > max_cells) {
    *error = sizeRefusal(path, w, h, max_cells);
    return false;
  }
  if (maxval == 0 || maxval > 255) {
    *error = "image '" + path + "': maxval must be 1..255, got " + max_token;
    return false;
  }
  // pnmToken consumed the single whitespace after maxval.
  GreyImage img;
  img.width = static_cast<int>(w);
  img.height = static_cast<int>(h);
  img.max_value = static_cast<int>(maxval);
  img.pixels.resize(static_cast<std::size_t>(w * h));
  for (auto& pixel : img.pixels) {
    std::uint64_t v = 0;
    if (magic == "P5") {
      const int c = in.get();
      if (c == EOF) {
        *error = "image '" + path + "': image data ends early";
        return false;
      }
      v = static_cast<std::uint64_t>(c);
    } else {
      std::string token;
      if (!pnmToken(in, &token) || !parseSize(token, &v)) {
        *error = "image '" + path + "': image data ends early";
        return false;
      }
    }
    pixel = static_cast<std::uint16_t>(std::min(v, maxval));
  }
  *image = std::move(img);
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

bool readGreyImage(const std::string& path, std::uint64_t max_cells, GreyImage* image, std::string* error) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    *error = "cannot read image '" + path + "'";
    return false;
  }
  char magic[2] = {};
  in.read(magic, 2);
  if (in.gcount() == 2 && magic[0] == 'P' && (magic[1] == '2' || magic[1] == '5')) {
    in.seekg(0);
    return readPgm(path, in, max_cells, image, error);
  }
  std::uint64_t header_w = 0, header_h = 0;
  if (readImageHeaderSize(path, &header_w, &header_h) &&
      (header_w == 0 || header_h == 0 || header_w * header_h > max_cells)) {
    *error = sizeRefusal(path, header_w, header_h, max_cells);
    return false;
  }
  cv::Mat img;
  try {
    img = cv::imread(path, cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception& e) {
    *error = "cannot decode image '" + path + "': " + e.what();
    return false;
  }
  if (img.empty()) {
    *error = "cannot read image '" + path + "'";
    return false;
  }
  if (static_cast<std::uint64_t>(img.cols) * static_cast<std::uint64_t>(img.rows) > max_cells) {
    *error = sizeRefusal(path, img.cols, img.rows, max_cells);
    return false;
  }
  image->width = img.cols;
  image->height = img.rows;
  image->max_value = 255;
  image->pixels.resize(static_cast<std::size_t>(img.cols) * static_cast<std::size_t>(img.rows));
  for (int r = 0; r < img.rows; ++r)
    for (int c = 0; c < img.cols; ++c)
      image->pixels[static_cast<std::size_t>(r) * img.cols + c] = img.at<std::uint8_t>(r, c);
  return true;
}

bool writePgm(const std::string& path, const GreyImage& image, std::string* error) {
  std::ofstream out(path, std::ios::binary);
  if (!out) {
    *error = "cannot write " + path;
    return false;
  }
  out << "P5\n# thorvald_map occupancy grid\n" << image.width << " " << image.height << "\n255\n";
  std::string bytes(image.pixels.size(), '\0');
  for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<char>(std::min<int>(image.pixels[i], 255));
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) {
    *error = "write failed: " + path;
    return false;
  }
  return true;
}

}  // namespace thorvald_map
