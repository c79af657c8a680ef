#include "cotton_harvester/perception/boll_circle_fit.h"

#include <algorithm>
#include <cmath>

namespace cotton_harvester {
namespace perception {

bool isBollCircle(const BollCircle& circle, const BollCircleLimits& limits) {
  const bool round = circle.rms_px <= std::max(0.75, limits.max_rms_fraction * circle.radius_px) &&
                     circle.arc_coverage_rad >= limits.min_arc_deg * CV_PI / 180.0;
  const bool boll_sized =
      circle.radius_px >= 0.7 * limits.radius_min_px && circle.radius_px <= 1.2 * limits.radius_max_px;
  return round && boll_sized;
}

bool holdsDisc(const BollCircle& circle, const cv::Point2d& centre, double radius) {
  // The inscribed radius comes from the closed region on the pixel grid: a pixel, or a tenth of the radius, of slack.
  return cv::norm(circle.centre - centre) + radius <= circle.radius_px + std::max(1.5, 0.1 * circle.radius_px);
}

std::optional<BollCircle> roundOutline(const std::vector<cv::Point>& outline, const BollCircleLimits& limits) {
  std::optional<BollCircle> circle = fitOuterCircle(outline);
  if (!circle || !isBollCircle(*circle, limits)) return std::nullopt;
  return circle;
}

std::vector<cv::Point2d> lobeOutline(const std::vector<cv::Point>& outline, const cv::Point2d& centre, double radius) {
  std::vector<cv::Point2d> points;
  const int n = static_cast<int>(outline.size());
  const int k = std::max(2, static_cast<int>(std::lround(0.25 * radius)));  // tangent over +-k outline pixels
  if (n < 2 * k + 1) return points;
  const double reach = 1.6 * radius + 1.0;
  for (int i = 0; i < n; ++i) {
    const cv::Point2d d = cv::Point2d(outline[i]) - centre;
    const double distance = std::hypot(d.x, d.y);
    if (distance > reach || distance <= 0.0) continue;
    const cv::Point2d t = cv::Point2d(outline[(i + k) % n] - outline[(i - k + n) % n]);
    const double length = std::hypot(t.x, t.y);
    if (length > 0.0 && std::abs(t.dot(d)) <= 0.5 * length * distance) points.push_back(cv::Point2d(outline[i]));
  }
  return points;
}

std::optional<BollCircle> lobeCircle(const std::vector<cv::Point>& outline, const cv::Point2d& centre, double radius,
                                     const BollCircleLimits& limits) {
  const std::vector<cv::Point2d> candidates = lobeOutline(outline, centre, radius);
  if (candidates.size() < 8) return std::nullopt;
  // Robust refit: the candidates within a tolerance of the previous circle (the outline of another boll or of a
  // sliver that passes the direction test lies off it); the tolerance is the roundness a boll's outline is allowed.
  std::optional<BollCircle> circle = fitCircle(candidates);
  std::vector<cv::Point2d> on_circle;
  for (int round = 0; round < 3 && circle; ++round) {
    const double tolerance = std::max(1.5, 2.0 * limits.max_rms_fraction * circle->radius_px);
    on_circle.clear();
    for (const cv::Point2d& p : candidates)
      if (std::abs(cv::norm(p - circle->centre) - circle->radius_px) <= tolerance) on_circle.push_back(p);
    if (on_circle.size() < 8) return std::nullopt;
    circle = fitCircle(on_circle);
  }
  if (!circle) return std::nullopt;
  circle->radius_px += 0.5;  // boundary pixel centres lie half a pixel inside the region's edge
  if (!isBollCircle(*circle, limits) || !holdsDisc(*circle, centre, radius)) return std::nullopt;
  return circle;
}

}  // namespace perception
}  // namespace cotton_harvester
