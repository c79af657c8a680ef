#include "greenhouse_rail_nav/depth_median.h"

#include <algorithm>
#include <cmath>
#include <vector>

namespace greenhouse_rail_nav {

OrganisedCloud medianAlongRays(const OrganisedCloud& cloud, int window) {
  if (window <= 1 || cloud.width <= 0 || cloud.height <= 0 ||
      cloud.points.size() != static_cast<std::size_t>(cloud.width) * static_cast<std::size_t>(cloud.height))
    return cloud;
  const int half = window / 2, w = cloud.width, h = cloud.height;
  const int needed = (window * window + 1) / 2;
  std::vector<float> range(cloud.points.size(), NAN);
  for (std::size_t i = 0; i < cloud.points.size(); ++i)
    if (cloud.points[i].allFinite()) range[i] = cloud.points[i].norm();
  OrganisedCloud out = cloud;
  std::vector<float> near;
  near.reserve(static_cast<std::size_t>(window * window));
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * w + u;
      if (!(range[i] > 0.0f)) continue;  // no depth (NaN) or at the camera: stays
      near.clear();
      for (int dv = std::max(0, v - half); dv <= std::min(h - 1, v + half); ++dv) {
        const float* row = &range[static_cast<std::size_t>(dv) * w];
        for (int du = std::max(0, u - half); du <= std::min(w - 1, u + half); ++du)
          if (std::isfinite(row[du])) near.push_back(row[du]);
      }
      if (static_cast<int>(near.size()) < needed) continue;
      auto mid = near.begin() + static_cast<std::ptrdiff_t>(near.size() / 2);
      std::nth_element(near.begin(), mid, near.end());
      out.points[i] = cloud.points[i] * (*mid / range[i]);
    }
  }
  return out;
}

}  // namespace greenhouse_rail_nav
