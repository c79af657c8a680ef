#include "thorvald_navigation/testing/synthetic_headland.h"

#include <algorithm>
#include <cmath>

namespace thorvald_navigation {
namespace testing {

SyntheticHeadland::SyntheticHeadland(const HeadlandOptions& o) : options_(o) {
  const double l = o.length_m, d = o.depth_m, far = o.depth_m + o.row_length_m;
  // Outer walls: the headland and the greenhouse beyond it.
  segments_.push_back({{0, 0}, {l, 0}});
  segments_.push_back({{l, 0}, {l, far}});
  segments_.push_back({{l, far}, {0, far}});
  segments_.push_back({{0, far}, {0, 0}});
  // Rows: every rail set has plant lines 0.35 m either side of its centre; an irregular start makes the map
  // less periodic, as real crops are.
  std::mt19937 rng(o.seed);
  std::uniform_real_distribution<double> jitter(0.0, 0.3);
  for (double x = o.row_spacing_m; x < l - 0.5; x += o.row_spacing_m) {
    for (double side : {-0.35, 0.35}) segments_.push_back({{x + side, d + jitter(rng)}, {x + side, far}});
  }
  std::uniform_real_distribution<double> bx(1.0, l - 1.0), by(0.6, std::max(0.7, d - 1.5));
  for (int i = 0; i < o.clutter_boxes; ++i) addBox({bx(rng), by(rng)}, o.box_size_m);
}

void SyntheticHeadland::addBox(const Eigen::Vector2d& c, double s) {
  const double h = 0.5 * s;
  const Eigen::Vector2d p0 = c + Eigen::Vector2d(-h, -h), p1 = c + Eigen::Vector2d(h, -h),
                        p2 = c + Eigen::Vector2d(h, h), p3 = c + Eigen::Vector2d(-h, h);
  segments_.push_back({p0, p1});
  segments_.push_back({p1, p2});
  segments_.push_back({p2, p3});
  segments_.push_back({p3, p0});
}

double SyntheticHeadland::castRay(const Eigen::Vector2d& o, double angle, double max_range) const {
  const Eigen::Vector2d dir(std::cos(angle), std::sin(angle));
  double best = max_range;
  for (const auto& s : segments_) {
    const Eigen::Vector2d e = s.b - s.a;
    const double den = dir.x() * e.y() - dir.y() * e.x();
    if (std::abs(den) < 1e-12) continue;
    const Eigen::Vector2d w = s.a - o;
    const double t = (w.x() * e.y() - w.y() * e.x()) / den;
    const double u = (w.x() * dir.y() - w.y() * dir.x()) / den;
    if (t > 1e-9 && u >= 0.0 && u <= 1.0) best = std::min(best, t);
  }
  return best;
}

std::vector<Eigen::Vector2d> SyntheticHeadland::scan(const thorvald_base::Pose2D& pose,
                                                     const Eigen::Vector2d& sensor_base, int beams, double angle_min,
                                                     double angle_max, double max_range, double noise_m,
                                                     std::mt19937* rng) const {
  std::normal_distribution<double> noise(0.0, noise_m);
  std::vector<Eigen::Vector2d> pts;
  const Eigen::Vector2d origin = pose.transformPoint(sensor_base);
  for (int i = 0; i < beams; ++i) {
    const double a = angle_min + (angle_max - angle_min) * i / std::max(1, beams - 1);
    const double r = castRay(origin, pose.yaw + a, max_range);
    if (r >= max_range) continue;
    const double rn = r + (noise_m > 0.0 ? noise(*rng) : 0.0);
    pts.push_back(sensor_base + rn * Eigen::Vector2d(std::cos(a), std::sin(a)));
  }
  return pts;
}

thorvald_map::OccupancyGrid SyntheticHeadland::truthMap(double res) const {
  const double far = options_.depth_m + options_.row_length_m;
  const double margin = 1.0;
  const int w = static_cast<int>(std::ceil((options_.length_m + 2 * margin) / res));
  const int h = static_cast<int>(std::ceil((far + 2 * margin) / res));
  thorvald_map::OccupancyGrid g(w, h, res, -margin, -margin, thorvald_map::kUnknown);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const Eigen::Vector2d c = g.cellCentre(x, y);
      if (c.x() > 0 && c.x() < options_.length_m && c.y() > 0 && c.y() < far) g.at(x, y) = thorvald_map::kFree;
    }
  for (const auto& s : segments_) {
    const int n = static_cast<int>(std::ceil((s.b - s.a).norm() / (0.25 * res))) + 1;
    for (int i = 0; i <= n; ++i) {
      const Eigen::Vector2i c = g.cellOf(s.a + (s.b - s.a) * (static_cast<double>(i) / n));
      if (g.inside(c.x(), c.y())) g.at(c.x(), c.y()) = thorvald_map::kOccupied;
    }
  }
  return g;
}

}  // namespace testing
}  // namespace thorvald_navigation
