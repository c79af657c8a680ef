#include "greenhouse_rail_nav/cloud_projection.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Dense>

namespace greenhouse_rail_nav {
namespace {

/// Least-squares pixel = f * ray + c over (ray, pixel) pairs; returns false on a degenerate spread.
bool fitAxis(const std::vector<Eigen::Vector2d>& samples, double* f, double* c, double* rms) {
  const double n = static_cast<double>(samples.size());
  double sa = 0, sp = 0, saa = 0, sap = 0;
  for (const auto& s : samples) {
    sa += s.x();
    sp += s.y();
    saa += s.x() * s.x();
    sap += s.x() * s.y();
  }
  const double var = saa - sa * sa / n;
  if (!(var > 1e-9 * n)) return false;
  *f = (sap - sa * sp / n) / var;
  *c = (sp - *f * sa) / n;
  double ss = 0.0;
  for (const auto& s : samples) {
    const double r = *f * s.x() + *c - s.y();
    ss += r * r;
  }
  *rms = std::sqrt(ss / n);
  return std::isfinite(*f) && *f > 0.0 && std::isfinite(*c);
}

}  // namespace

std::optional<CloudProjection> CloudProjection::fromCloud(const OrganisedCloud& cloud, int stride, double max_rms_px) {
  if (cloud.width < 2 || cloud.height < 2 || stride < 1 ||
      static_cast<std::size_t>(cloud.width) * static_cast<std::size_t>(cloud.height) != cloud.points.size())
    return std::nullopt;
  std::vector<Eigen::Vector2d> us, vs;  // (ray slope, pixel)
  int u_lo = cloud.width, u_hi = -1, v_lo = cloud.height, v_hi = -1;
  for (int v = 0; v < cloud.height; v += stride) {
    for (int u = 0; u < cloud.width; u += stride) {
      const Eigen::Vector3f& p = cloud.points[static_cast<std::size_t>(v) * cloud.width + u];
      if (!p.allFinite() || !(p.z() > 1e-3f)) continue;
      us.emplace_back(p.x() / p.z(), u);
      vs.emplace_back(p.y() / p.z(), v);
      u_lo = std::min(u_lo, u);
      u_hi = std::max(u_hi, u);
      v_lo = std::min(v_lo, v);
      v_hi = std::max(v_hi, v);
    }
  }
  // The samples must span a good part of the image both ways, or the slopes are poorly determined.
  if (us.size() < 20 || u_hi - u_lo < cloud.width / 4 || v_hi - v_lo < cloud.height / 4) return std::nullopt;
  DepthCameraIntrinsics k;
  k.width = cloud.width;
  k.height = cloud.height;
  double rms_u = 0.0, rms_v = 0.0;
  if (!fitAxis(us, &k.fx, &k.cx, &rms_u) || !fitAxis(vs, &k.fy, &k.cy, &rms_v)) return std::nullopt;
  if (rms_u > max_rms_px || rms_v > max_rms_px) return std::nullopt;
  return CloudProjection(k);
}

bool CloudProjection::inImage(const Eigen::Vector3d& point, double margin_px) const {
  if (!(point.z() > 1e-3)) return false;
  const double u = k_.fx * point.x() / point.z() + k_.cx;
  const double v = k_.fy * point.y() / point.z() + k_.cy;
  return u >= margin_px && v >= margin_px && u <= k_.width - 1 - margin_px && v <= k_.height - 1 - margin_px;
}

}  // namespace greenhouse_rail_nav
