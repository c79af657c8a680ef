#include "thorvald_navigation/distance_field.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace thorvald_navigation {
namespace {

// Squared-distance transform of one line (Felzenszwalb & Huttenlocher's lower envelope of parabolas). Cells
// without a wall hold a large finite value so that the envelope arithmetic stays finite.
// `arg` (optional) receives the index of the nearest wall cell of each cell.
void transform1d(const std::vector<double>& f, std::vector<double>* d, std::vector<int>* v, std::vector<double>* z,
                 std::vector<int>* arg = nullptr) {
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
    if (arg) (*arg)[q] = vk;
  }
}

}  // namespace

namespace {

// A wall cell with a known-free 4-neighbour: the row of cells that holds a wall's face, seen from the free side.
bool isFaceCell(const thorvald_map::OccupancyGrid& grid, int x, int y) {
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

DistanceField::DistanceField(const thorvald_map::OccupancyGrid& grid, double max_distance_m, int occupied_threshold,
                             bool faces_only, const thorvald_map::WallSurface* surface, double line_half_length_m)
    : width_(grid.width),
      height_(grid.height),
      resolution_m_(grid.resolution_m),
      origin_x_m_(grid.origin.x),
      origin_y_m_(grid.origin.y),
      max_distance_m_(max_distance_m),
      occupied_threshold_(occupied_threshold) {
  if (width_ <= 0 || height_ <= 0 || grid.data.size() != static_cast<std::size_t>(width_) * height_) {
    width_ = height_ = 0;
    return;
  }
  const std::size_t n = grid.data.size();
  line_half_length_m_ = line_half_length_m < 0.0    ? static_cast<float>(0.5 * resolution_m_)
                        : line_half_length_m == 0.0 ? std::numeric_limits<float>::infinity()
                                                    : static_cast<float>(line_half_length_m);
  reach_cells_ = static_cast<int>(std::ceil(max_distance_m_ / resolution_m_)) + 1;
  // A grid without any face cell (nothing seen from the inside) keeps every wall cell.
  faces_ = false;
  if (faces_only)
    for (int y = 0; y < height_ && !faces_; ++y)
      for (int x = 0; x < width_ && !faces_; ++x)
        faces_ = grid.at(x, y) >= occupied_threshold_ && isFaceCell(grid, x, y);
  site_.assign(n, 0);
  for (int y = 0; y < height_; ++y)
    for (int x = 0; x < width_; ++x)
      if (isSite(grid, x, y)) {
        site_[grid.index(x, y)] = 1;
        ++occupied_cells_;
      }
  sub_cell_ = surface && surface->check(n).empty() && occupied_cells_ > 0;
  dist_.assign(n, static_cast<float>(max_distance_m_));
  if (sub_cell_) {
    site_of_.assign(n, -1);
    surfel_.assign(n, Surfel{});
  }
  transformWindow(0, 0, width_ - 1, height_ - 1, 0, 0, width_ - 1, height_ - 1);
  if (sub_cell_)
    for (int y = 0; y < height_; ++y)
      for (int x = 0; x < width_; ++x)
        if (site_[grid.index(x, y)]) computeSurfel(*surface, x, y);
}

bool DistanceField::isSite(const thorvald_map::OccupancyGrid& grid, int x, int y) const {
  return grid.at(x, y) >= occupied_threshold_ && (!faces_ || isFaceCell(grid, x, y));
}

void DistanceField::transformWindow(int wx0, int wy0, int wx1, int wy1, int bx0, int by0, int bx1, int by1) {
  const int w = wx1 - wx0 + 1, h = wy1 - wy0 + 1;
  const std::size_t n = static_cast<std::size_t>(w) * h;
  const double far = 4.0 * (static_cast<double>(w) + h) * (static_cast<double>(w) + h);
  std::vector<double> sq(n, far);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (site_[static_cast<std::size_t>(y + wy0) * width_ + (x + wx0)]) sq[static_cast<std::size_t>(y) * w + x] = 0.0;
  const int longest = std::max(w, h);
  std::vector<double> f(longest), d(longest), z(longest + 1);
  std::vector<int> v(longest + 1), arg(longest);
  // Feature transform alongside: the row of the nearest wall cell in each cell's column, then its column.
  std::vector<int> near_row(sub_cell_ ? n : 0);
  f.resize(h);
  d.resize(h);
  arg.resize(h);
  for (int x = 0; x < w; ++x) {  // columns
    for (int y = 0; y < h; ++y) f[y] = sq[static_cast<std::size_t>(y) * w + x];
    transform1d(f, &d, &v, &z, sub_cell_ ? &arg : nullptr);
    for (int y = 0; y < h; ++y) {
      sq[static_cast<std::size_t>(y) * w + x] = d[y];
      if (sub_cell_) near_row[static_cast<std::size_t>(y) * w + x] = arg[y];
    }
  }
  f.resize(w);
  d.resize(w);
  arg.resize(w);
  for (int y = by0 - wy0; y <= by1 - wy0; ++y) {  // rows: only those of the box
    for (int x = 0; x < w; ++x) f[x] = sq[static_cast<std::size_t>(y) * w + x];
    transform1d(f, &d, &v, &z, sub_cell_ ? &arg : nullptr);
    for (int x = bx0 - wx0; x <= bx1 - wx0; ++x) {
      const std::size_t i = static_cast<std::size_t>(y + wy0) * width_ + (x + wx0);
      dist_[i] = static_cast<float>(std::min(max_distance_m_, std::sqrt(d[x]) * resolution_m_));
      if (sub_cell_) {
        const int cx = arg[x], cy = near_row[static_cast<std::size_t>(y) * w + cx];
        site_of_[i] = d[x] < far ? (cy + wy0) * width_ + (cx + wx0) : -1;
      }
    }
  }
}

void DistanceField::update(const thorvald_map::OccupancyGrid& grid, const thorvald_map::WallSurface* surface,
                           const std::vector<int>& changed_cells, const std::vector<int>& moved_cells) {
  if (width_ == 0 || grid.width != width_ || grid.height != height_ || grid.data.size() != dist_.size()) return;
  const int n = static_cast<int>(dist_.size());
  // Site flags of the changed cells and their 4-neighbours (a face cell is one with a free 4-neighbour).
  constexpr int kTile = 32;
  const int tiles_x = (width_ + kTile - 1) / kTile, tiles_y = (height_ + kTile - 1) / kTile;
  std::vector<std::uint8_t> dirty(static_cast<std::size_t>(tiles_x) * tiles_y, 0);
  std::vector<int> surfel_cells;
  for (const int i : changed_cells) {
    if (i < 0 || i >= n) continue;
    const int cx = i % width_, cy = i / width_;
    const int nb[5][2] = {{0, 0}, {1, 0}, {-1, 0}, {0, 1}, {0, -1}};
    for (const auto& o : nb) {
      const int x = cx + o[0], y = cy + o[1];
      if (!grid.inside(x, y)) continue;
      const std::size_t j = grid.index(x, y);
      const std::uint8_t now = isSite(grid, x, y) ? 1 : 0;
      if (now == site_[j]) continue;
      occupied_cells_ += now ? 1 : -1;
      site_[j] = now;
      dirty[static_cast<std::size_t>(y / kTile) * tiles_x + x / kTile] = 1;
      if (now) surfel_cells.push_back(static_cast<int>(j));
    }
  }
  // Distances (and nearest sites) within reach of a tile whose sites changed: the tile grown by the reach, from a
  // window grown by the reach once more.
  const int r = reach_cells_ + 1;
  for (int ty = 0; ty < tiles_y; ++ty)
    for (int tx = 0; tx < tiles_x; ++tx) {
      if (!dirty[static_cast<std::size_t>(ty) * tiles_x + tx]) continue;
      const int bx0 = std::max(0, tx * kTile - r), by0 = std::max(0, ty * kTile - r);
      const int bx1 = std::min(width_ - 1, (tx + 1) * kTile - 1 + r),
                by1 = std::min(height_ - 1, (ty + 1) * kTile - 1 + r);
      transformWindow(std::max(0, bx0 - r), std::max(0, by0 - r), std::min(width_ - 1, bx1 + r),
                      std::min(height_ - 1, by1 + r), bx0, by0, bx1, by1);
    }
  if (!sub_cell_ || !surface || !surface->check(dist_.size()).empty()) return;
  // Surfels whose 3x3 neighbourhood gained end points, and new sites.
  for (const int i : moved_cells) {
    if (i < 0 || i >= n) continue;
    const int cx = i % width_, cy = i / width_;
    for (int y = std::max(0, cy - 1); y <= std::min(height_ - 1, cy + 1); ++y)
      for (int x = std::max(0, cx - 1); x <= std::min(width_ - 1, cx + 1); ++x)
        if (site_[grid.index(x, y)]) computeSurfel(*surface, x, y);
  }
  for (const int i : surfel_cells) computeSurfel(*surface, i % width_, i / width_);
}

// A site's surfel: the hits of its 3x3 neighbourhood give the point (their mean, which also holds the hits that noise
// put in the cell behind or in front of the face) and the direction (their principal axis). A wall cell without hits
// around it (a map drawn by hand) keeps its centre as a point.
void DistanceField::computeSurfel(const thorvald_map::WallSurface& surface, int sx, int sy) {
  double w = 0.0;
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();
  Eigen::Matrix2d sum_sq = Eigen::Matrix2d::Zero();
  for (int y = std::max(0, sy - 1); y <= std::min(height_ - 1, sy + 1); ++y)
    for (int x = std::max(0, sx - 1); x <= std::min(width_ - 1, sx + 1); ++x) {
      const std::size_t j = static_cast<std::size_t>(y) * width_ + x;
      const double h = surface.hits[j];
      if (!(h > 0.0) || !surface.mean_m[j].allFinite()) continue;
      const Eigen::Vector2d m = surface.mean_m[j].cast<double>();
      w += h;
      sum += h * m;
      sum_sq += h * m * m.transpose();
    }
  Surfel s;
  const Eigen::Vector2d centre(origin_x_m_ + (sx + 0.5) * resolution_m_, origin_y_m_ + (sy + 0.5) * resolution_m_);
  Eigen::Vector2d point = centre;
  if (w > 0.0) {
    point = sum / w;
    // Keep the point within the site's neighbourhood (bad input cannot move a wall farther than a cell).
    if ((point - centre).cwiseAbs().maxCoeff() > 1.5 * resolution_m_) point = centre;
    const Eigen::Matrix2d cov = sum_sq / w - point * point.transpose();
    const double a = cov(0, 0), b = cov(0, 1), c = cov(1, 1);
    const double l1 = 0.5 * (a + c) + std::sqrt(0.25 * (a - c) * (a - c) + b * b), l2 = a + c - l1;
    // A clear line (one direction much wider than the other): a segment (by default one cell long); else a point.
    if (l1 > 4.0 * std::max(l2, 0.0) && l1 > 0.01 * resolution_m_ * resolution_m_) {
      const Eigen::Vector2d t = std::abs(b) > 1e-15 ? Eigen::Vector2d(l1 - c, b).normalized()
                                                    : (a >= c ? Eigen::Vector2d::UnitX() : Eigen::Vector2d::UnitY());
      s.tangent = t.cast<float>();
      s.half_length = line_half_length_m_;
    }
  }
  s.point = point.cast<float>();
  surfel_[static_cast<std::size_t>(sy) * width_ + sx] = s;
}

double DistanceField::surfaceDistance(const Eigen::Vector2d& p, Eigen::Vector2d* gradient) const {
  const int cx = static_cast<int>(std::floor((p.x() - origin_x_m_) / resolution_m_));
  const int cy = static_cast<int>(std::floor((p.y() - origin_y_m_) / resolution_m_));
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector2d best_dir = Eigen::Vector2d::Zero();
  int seen[9];
  int n_seen = 0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) {
      const int x = cx + dx, y = cy + dy;
      if (x < 0 || y < 0 || x >= width_ || y >= height_) continue;
      const int k = site_of_[static_cast<std::size_t>(y) * width_ + x];
      if (k < 0 || std::find(seen, seen + n_seen, k) != seen + n_seen) continue;
      seen[n_seen++] = k;
      const Surfel& s = surfel_[static_cast<std::size_t>(k)];
      const Eigen::Vector2d tangent = s.tangent.cast<double>();
      const Eigen::Vector2d r = p - s.point.cast<double>();
      const double t =
          std::clamp(r.dot(tangent), -static_cast<double>(s.half_length), static_cast<double>(s.half_length));
      const Eigen::Vector2d e = r - t * tangent;
      const double dist = e.norm();
      if (dist < best) {
        best = dist;
        best_dir = e;
      }
    }
  if (!(best < max_distance_m_)) {
    if (gradient) gradient->setZero();
    return max_distance_m_;
  }
  if (gradient) {
    if (best > 1e-12) {
      *gradient = best_dir / best;
    } else {
      gradient->setZero();
    }
  }
  return best;
}

double DistanceField::distance(const Eigen::Vector2d& p, Eigen::Vector2d* gradient) const {
  if (sub_cell_) {
    const double gx = (p.x() - origin_x_m_) / resolution_m_, gy = (p.y() - origin_y_m_) / resolution_m_;
    if (!(gx >= 0.0 && gy >= 0.0 && gx < width_ && gy < height_)) {
      if (gradient) gradient->setZero();
      return max_distance_m_;
    }
    return surfaceDistance(p, gradient);
  }
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
