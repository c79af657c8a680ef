#include "thorvald_sim/lidar_model.h"

#include <cmath>
#include <limits>

namespace thorvald_sim {

double lidarSigma(const LidarModel& m, double range_m) {
  return range_m <= m.near_limit_m ? m.sigma_near_m : m.sigma_far_m;
}

bool lidarReturns(const LidarModel& m, double range_m, double incidence_rad) {
  if (range_m < 0.0 || incidence_rad > m.max_incidence_rad) return false;
  const double r = range_m / m.white_range_m;
  return m.reflectance * std::cos(incidence_rad) >= r * r;
}

std::vector<float> applyLidarModel(const std::vector<LidarBeam>& beams, double range_min_m, double range_max_m,
                                   const LidarModel& m, std::mt19937& rng) {
  const size_t n = beams.size();
  // Which beams return at all: a target in range, not glancing, not dropped.
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::vector<double> range(n, -1.0);
  for (size_t i = 0; i < n; ++i) {
    const LidarBeam& b = beams[i];
    if (!lidarReturns(m, b.range_m, b.incidence_rad)) continue;
    if (m.dropout > 0.0 && uni(rng) < m.dropout) continue;
    range[i] = b.range_m;
  }
  // Mixed pixels: the nearer beam of a pair across an edge sees part of the farther surface too. The edge is judged
  // on the true ranges (a beam behind an edge sees the background even when it returned nothing).
  std::vector<double> out = range;
  for (size_t i = 0; i + 1 < n; ++i) {
    const double a = beams[i].range_m, b = beams[i + 1].range_m;
    if (a < 0.0 || b < 0.0 || std::fabs(a - b) <= m.edge_jump_m) continue;
    const size_t near = a < b ? i : i + 1;
    if (range[near] < 0.0 || uni(rng) >= m.mixed_probability) continue;
    out[near] = std::min(a, b) + uni(rng) * std::fabs(a - b);
  }
  std::normal_distribution<double> unit(0.0, 1.0);
  std::vector<float> ranges(n, std::numeric_limits<float>::infinity());
  for (size_t i = 0; i < n; ++i) {
    if (out[i] < 0.0) continue;
    const double r = out[i] + lidarSigma(m, out[i]) * unit(rng);
    if (r >= range_min_m && r <= range_max_m) ranges[i] = static_cast<float>(r);
  }
  return ranges;
}

}  // namespace thorvald_sim
