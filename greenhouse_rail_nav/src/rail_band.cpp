#include "greenhouse_rail_nav/rail_band.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

namespace greenhouse_rail_nav {

std::vector<Eigen::Vector3f> thinToVoxels(const std::vector<Eigen::Vector3f>& points, double voxel_m) {
  if (voxel_m <= 0.0 || points.empty()) return points;
  const float inv = static_cast<float>(1.0 / voxel_m);
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed;
  keyed.reserve(points.size());
  for (std::uint32_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3f& p = points[i];
    // 21 bits per axis with an offset: +-10 km at 1 cm voxels is far beyond any crop box.
    const auto cell = [&](float v) { return static_cast<std::uint64_t>(std::floor(v * inv) + (1 << 20)) & 0x1FFFFF; };
    keyed.emplace_back((cell(p.x()) << 42) | (cell(p.y()) << 21) | cell(p.z()), i);
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<Eigen::Vector3f> out;
  for (std::size_t i = 0; i < keyed.size();) {
    Eigen::Vector3f sum = Eigen::Vector3f::Zero();
    std::size_t j = i;
    for (; j < keyed.size() && keyed[j].first == keyed[i].first; ++j) sum += points[keyed[j].second];
    out.push_back(sum / static_cast<float>(j - i));
    i = j;
  }
  return out;
}

std::vector<Eigen::Vector2d> xyOf(const std::vector<Eigen::Vector3f>& points) {
  std::vector<Eigen::Vector2d> xy;
  xy.reserve(points.size());
  for (const auto& p : points) xy.emplace_back(p.x(), p.y());
  return xy;
}

std::vector<Eigen::Vector2d> xyOf(const std::vector<Eigen::Vector3f>& points, const std::vector<int>& indices) {
  std::vector<Eigen::Vector2d> xy;
  xy.reserve(indices.size());
  for (const int i : indices)
    xy.emplace_back(points[static_cast<std::size_t>(i)].x(), points[static_cast<std::size_t>(i)].y());
  return xy;
}

double medianHeight(const std::vector<Eigen::Vector3f>& points, const std::vector<int>& indices) {
  std::vector<float> z;
  z.reserve(indices.size());
  for (const int i : indices) z.push_back(points[static_cast<std::size_t>(i)].z());
  if (z.empty()) return 0.0;
  std::nth_element(z.begin(), z.begin() + static_cast<std::ptrdiff_t>(z.size() / 2), z.end());
  return z[z.size() / 2];
}

}  // namespace greenhouse_rail_nav
