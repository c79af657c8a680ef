#include "cotton_harvester/perception/boll_circle.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace cotton_harvester {
namespace perception {

std::optional<BollCircle> fitCircle(const std::vector<cv::Point2d>& points) {
  if (points.size() < 3) return std::nullopt;
  // Centred on the mean for conditioning: minimise sum (x^2 + y^2 + D x + E y + F)^2.
  cv::Point2d mean(0.0, 0.0);
  for (const cv::Point2d& p : points) mean += p;
  mean *= 1.0 / static_cast<double>(points.size());
  cv::Matx33d normal = cv::Matx33d::zeros();
  cv::Vec3d rhs(0.0, 0.0, 0.0);
  for (const cv::Point2d& p : points) {
    const double x = p.x - mean.x, y = p.y - mean.y;
    const cv::Vec3d row(x, y, 1.0);
    const double target = -(x * x + y * y);
    for (int i = 0; i < 3; ++i) {
      rhs[i] += row[i] * target;
      for (int j = 0; j < 3; ++j) normal(i, j) += row[i] * row[j];
    }
  }
  cv::Vec3d solution;
  if (!cv::solve(normal, rhs, solution, cv::DECOMP_LU)) return std::nullopt;
  const double cx = -0.5 * solution[0], cy = -0.5 * solution[1];
  const double r2 = cx * cx + cy * cy - solution[2];
  if (!(r2 > 0.0) || !std::isfinite(r2)) return std::nullopt;
  BollCircle circle;
  circle.centre = {cx + mean.x, cy + mean.y};
  circle.radius_px = std::sqrt(r2);
  double squares = 0.0;
  std::vector<double> angles;
  angles.reserve(points.size());
  for (const cv::Point2d& p : points) {
    const cv::Point2d d = p - circle.centre;
    const double e = std::hypot(d.x, d.y) - circle.radius_px;
    squares += e * e;
    angles.push_back(std::atan2(d.y, d.x));
  }
  circle.rms_px = std::sqrt(squares / points.size());
  circle.points = static_cast<int>(points.size());
  // Coverage: the angle spanned by runs of neighbouring points at most 4 px of arc apart (a few isolated points,
  // such as a rectangle's corners, lie on a circle too but cover none of it).
  std::sort(angles.begin(), angles.end());
  const double max_gap = 4.0 / circle.radius_px;
  double covered = 0.0;
  for (size_t i = 0; i < angles.size(); ++i) {
    const double next = i + 1 < angles.size() ? angles[i + 1] : angles.front() + 2.0 * CV_PI;
    if (next - angles[i] <= max_gap) covered += next - angles[i];
  }
  circle.arc_coverage_rad = std::min(covered, 2.0 * CV_PI);
  return circle;
}

std::optional<BollCircle> fitOuterCircle(const std::vector<cv::Point>& outline, double hull_tolerance_px) {
  if (outline.size() < 5) return std::nullopt;
  std::vector<cv::Point> hull;
  cv::convexHull(outline, hull);
  if (hull.size() < 3) return std::nullopt;
  // A straight cut (the image border, a straight leaf edge, the line between touching bolls) is itself a hull edge:
  // only its ends lie on the boll's circle. Hull edges longer than a digital circle's longest straight run (about
  // 2 sqrt(r) for radius r, here from the hull's extent) are such cuts; points inside them are left out.
  const cv::Rect extent = cv::boundingRect(hull);
  const double radius_guess = 0.5 * std::max(extent.width, extent.height);
  const double longest_run = 2.0 * std::sqrt(radius_guess) + 3.0;
  std::vector<std::pair<cv::Point2d, cv::Point2d>> cuts;
  for (size_t i = 0; i < hull.size(); ++i) {
    const cv::Point2d a = hull[i], b = hull[(i + 1) % hull.size()];
    if (cv::norm(b - a) > longest_run) cuts.emplace_back(a, b);
  }
  const auto onCut = [&cuts, hull_tolerance_px](const cv::Point2d& p) {
    for (const auto& [a, b] : cuts) {
      const cv::Point2d ab = b - a;
      const double t = (p - a).dot(ab) / ab.dot(ab);
      const double along = t * std::sqrt(ab.dot(ab));
      if (along < 1.5 || along > std::sqrt(ab.dot(ab)) - 1.5) continue;  // its ends are the circle's
      if (cv::norm(p - (a + t * ab)) <= hull_tolerance_px) return true;
    }
    return false;
  };
  std::vector<cv::Point2d> outer;
  outer.reserve(outline.size());
  for (const cv::Point& p : outline) {
    // pointPolygonTest: positive inside, 0 on the hull; every outline point is inside or on it.
    if (cv::pointPolygonTest(hull, cv::Point2f(p), true) <= hull_tolerance_px && !onCut(p)) outer.emplace_back(p);
  }
  if (outer.size() < 5) return std::nullopt;
  std::optional<BollCircle> circle = fitCircle(outer);
  if (circle) circle->radius_px += 0.5;  // boundary pixel centres lie half a pixel inside the region's edge
  return circle;
}

}  // namespace perception
}  // namespace cotton_harvester
