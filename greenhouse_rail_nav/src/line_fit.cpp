#include "greenhouse_rail_nav/line_fit.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

namespace greenhouse_rail_nav {

void LineFit2D::flip() {
  direction = -direction;
  const double lo = -s_max;
  s_max = -s_min;
  s_min = lo;
}

LineFit2D fitLine(const std::vector<Eigen::Vector2d>& points) {
  LineFit2D fit;
  fit.count = points.size();
  if (points.size() < 2) {
    if (!points.empty()) fit.centroid = points.front();
    return fit;
  }
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (const auto& p : points) {
    const Eigen::Vector2d d = p - mean;
    scatter += d * d.transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(scatter);
  const double l_min = std::max(0.0, solver.eigenvalues()(0));
  const double l_max = solver.eigenvalues()(1);
  fit.centroid = mean;
  if (l_max <= 0.0) return fit;  // all points coincide
  fit.direction = solver.eigenvectors().col(1).normalized();
  fit.linearity = 1.0 - l_min / l_max;
  fit.rms_residual = std::sqrt(l_min / static_cast<double>(points.size()));
  fit.s_min = std::numeric_limits<double>::max();
  fit.s_max = std::numeric_limits<double>::lowest();
  for (const auto& p : points) {
    const double s = fit.along(p);
    fit.s_min = std::min(fit.s_min, s);
    fit.s_max = std::max(fit.s_max, s);
  }
  return fit;
}

double angleBetweenLines(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return std::acos(std::min(1.0, std::abs(a.dot(b))));
}

bool perpendicular(const LineFit2D& a, const LineFit2D& b, double tolerance) {
  return std::abs(M_PI / 2 - angleBetweenLines(a.direction, b.direction)) <= tolerance;
}

}  // namespace greenhouse_rail_nav
