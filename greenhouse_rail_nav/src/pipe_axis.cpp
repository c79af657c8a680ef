#include "greenhouse_rail_nav/pipe_axis.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

namespace greenhouse_rail_nav {

RailLine pipeAxisLine(const RailLine& rail, const Eigen::Vector3d& camera_xyz,
                      const std::vector<Eigen::Vector3f>& raw_band, double pipe_radius_m) {
  const double r = pipe_radius_m;
  if (r <= 0.0) return rail;
  const Eigen::Vector2d left(-rail.fit.direction.y(), rail.fit.direction.x());
  // Start: the mean offset of the visible half of a cylinder sampled by projected area. In the plane across
  // the pipe the camera sits at lateral distance h and height v above the pipe's centre; that mean lies
  // pi/4 * r * cos(elevation) nearer the camera than the axis.
  const double h = rail.fit.signedDistance(camera_xyz.head<2>());
  const double v = camera_xyz.z() - (rail.height_m - 0.5 * r);
  const double cos_elevation = std::abs(h) / std::max(1e-6, std::hypot(h, v));
  const double model_offset = -(h >= 0.0 ? 1.0 : -1.0) * M_PI / 4.0 * r * cos_elevation;
  RailLine out = rail;
  out.fit.centroid += model_offset * left;

  // Circle of radius r across the rail, fitted to the raw points near the line (lateral offset d, height z):
  // Gauss-Newton on (|q - c| - r), points weighted by 1 / range^4 (active-stereo depth noise grows with
  // range^2), points more than 8 mm off the circle dropped after the first steps (leaves, flying pixels).
  std::vector<Eigen::Vector2d> q;
  std::vector<double> w;
  const Eigen::Vector3d cam = camera_xyz;
  for (const auto& b : raw_band) {
    const Eigen::Vector2d xy(b.x(), b.y());
    const double d = rail.fit.signedDistance(xy), s = rail.fit.along(xy);
    if (std::abs(d) > r + 0.015 || s < rail.fit.s_min - 0.02 || s > rail.fit.s_max + 0.02) continue;
    const double range = std::max(0.3, (b.cast<double>() - cam).norm());
    q.emplace_back(d, b.z());
    w.push_back(1.0 / (range * range * range * range));
  }
  if (q.size() < 20) return out;
  Eigen::Vector2d c(model_offset, rail.height_m - 0.5 * r);
  for (int iteration = 0; iteration < 12; ++iteration) {
    const double cutoff = iteration < 3 ? 0.03 : 0.008;
    Eigen::Matrix2d jtj = Eigen::Matrix2d::Zero();
    Eigen::Vector2d jte = Eigen::Vector2d::Zero();
    std::size_t used = 0;
    for (std::size_t i = 0; i < q.size(); ++i) {
      const Eigen::Vector2d diff = q[i] - c;
      const double dist = diff.norm();
      const double e = dist - r;
      if (dist < 1e-6 || std::abs(e) > cutoff) continue;
      const Eigen::Vector2d j = -diff / dist;
      jtj += w[i] * j * j.transpose();
      jte += w[i] * j * e;
      ++used;
    }
    if (used < 20 || jtj.determinant() <= 1e-12 * jtj.trace() * jtj.trace()) return out;
    const Eigen::Vector2d step = -jtj.ldlt().solve(jte);
    c += step;
    if (!c.allFinite() || std::abs(c.x()) > 2.0 * r) return out;  // diverged: keep the model's offset
    if (step.norm() < 1e-5 && iteration >= 4) break;
  }
  out.fit.centroid = rail.fit.centroid + c.x() * left;
  return out;
}

}  // namespace greenhouse_rail_nav
