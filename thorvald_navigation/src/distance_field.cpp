#include "thorvald_navigation/distance_field.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace thorvald_navigation {
namespace {

// Squared-distance transform of one line (Felzenszwalb & Huttenlocher's lower envelope of parabolas). Cells
// without a wall hold a large finite value so that the envelope arithmetic stays finite.
void transform1d(const std::vector<double>& f, std::vector<double>* d, std::vector<int>* v, std::vector<double>* z) {
  const int n = static_cast<int>(f.size());
  constexpr double kInf = std::numeric_limits<double>::infinity();
  int k = 0;
  (*v)[0] = 0;
  (*z)[0] = -kInf;
  (*z)[1] = kInf;
  for (int q = 1; q < n; ++q) {
    double s = 0.0;
    for (;;) {
      const int vk = (*v)[k];
      s = ((f[q] + static_cast<double>(q) * q) - (f[vk] + static_cast<double>(vk) * vk)) / (2.0 * q - 2.0 * vk);
      if (s <= (*z)[k] && k > 0) {
        --k;
      } else {
        break;
      }
    }
    ++k;
    (*v)[k] = q;
    (*z)[k] = s;
    (*z)[k + 1] = kInf;
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while ((*z)[k + 1] < q) ++k;
    const int vk = (*v)[k];
    (*d)[q] = static_cast<double>(q - vk) * (q - vk) + f[vk];
  }
}

}  // namespace

namespace {

// A wall cell with a known-free 4-neighbour: the row of cells that holds a wall's face, seen from the free side.
bool isFaceCell(const Grid2D& grid, int x, int y) {
  constexpr int kFreeBelow = 25;  // map_server's free_thresh is 0.196
  const int nb[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  for (const auto& d : nb) {
    const int nx = x + d[0], ny = y + d[1];
    if (!grid.inside(nx, ny)) continue;
    const int v = grid.at(nx, ny);
    if (v >= 0 && v < kFreeBelow) return true;
  }
  return false;
}

}  // namespace

DistanceField::DistanceField(const Grid2D& grid, double max_distance_m, int occupied_threshold, bool faces_only)
    : width_(grid.width),
      height_(grid.height),
      resolution_m_(grid.resolution_m),
      origin_x_m_(grid.origin_x_m),
      origin_y_m_(grid.origin_y_m),
      max_distance_m_(max_distance_m) {
  const std::size_t n = static_cast<std::size_t>(width_) * height_;
  const double far = 4.0 * (static_cast<double>(width_) + height_) * (static_cast<double>(width_) + height_);
  std::vector<double> sq(n, far);
  for (std::size_t i = 0; i < n && i < grid.data.size(); ++i) {
    if (grid.data[i] >= occupied_threshold) {
      sq[i] = 0.0;
      ++occupied_cells_;
    }
  }
  if (faces_only && grid.data.size() >= n) {
    std::vector<double> faces(n, far);
    int face_cells = 0;
    for (int y = 0; y < height_; ++y)
      for (int x = 0; x < width_; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * width_ + x;
        if (sq[i] == 0.0 && isFaceCell(grid, x, y)) {
          faces[i] = 0.0;
          ++face_cells;
        }
      }
    if (face_cells > 0) {  // a grid without free space (nothing seen from the inside) keeps every wall cell
      sq.swap(faces);
      occupied_cells_ = face_cells;
    }
  }
  if (width_ <= 0 || height_ <= 0) {
    width_ = height_ = 0;
    return;
  }
  const int longest = std::max(width_, height_);
  std::vector<double> f(longest), d(longest), z(longest + 1);
  std::vector<int> v(longest + 1);
  f.resize(height_);
  d.resize(height_);
  for (int x = 0; x < width_; ++x) {  // columns
    for (int y = 0; y < height_; ++y) f[y] = sq[static_cast<std::size_t>(y) * width_ + x];
    transform1d(f, &d, &v, &z);
    for (int y = 0; y < height_; ++y) sq[static_cast<std::size_t>(y) * width_ + x] = d[y];
  }
  f.resize(width_);
  d.resize(width_);
  for (int y = 0; y < height_; ++y) {  // rows
    for (int x = 0; x < width_; ++x) f[x] = sq[static_cast<std::size_t>(y) * width_ + x];
    transform1d(f, &d, &v, &z);
    for (int x = 0; x < width_; ++x) sq[static_cast<std::size_t>(y) * width_ + x] = d[x];
  }
  dist_.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    dist_[i] = static_cast<float>(std::min(max_distance_m_, std::sqrt(sq[i]) * resolution_m_));
}

double DistanceField::distance(const Eigen::Vector2d& p, Eigen::Vector2d* gradient) const {
  // Bilinear interpolation between the four surrounding cell centres.
  const double gx = (p.x() - origin_x_m_) / resolution_m_ - 0.5;
  const double gy = (p.y() - origin_y_m_) / resolution_m_ - 0.5;
  if (!(gx >= 0.0 && gy >= 0.0 && gx < width_ - 1 && gy < height_ - 1)) {
    if (gradient) gradient->setZero();
    return max_distance_m_;
  }
  const int x0 = static_cast<int>(gx), y0 = static_cast<int>(gy);
  const double fx = gx - x0, fy = gy - y0;
  const std::size_t i = static_cast<std::size_t>(y0) * width_ + x0;
  const double d00 = dist_[i], d10 = dist_[i + 1], d01 = dist_[i + width_], d11 = dist_[i + width_ + 1];
  if (gradient) {
    gradient->x() = ((d10 - d00) * (1.0 - fy) + (d11 - d01) * fy) / resolution_m_;
    gradient->y() = ((d01 - d00) * (1.0 - fx) + (d11 - d10) * fx) / resolution_m_;
  }
  return (d00 * (1.0 - fx) + d10 * fx) * (1.0 - fy) + (d01 * (1.0 - fx) + d11 * fx) * fy;
}

}  // namespace thorvald_navigation
