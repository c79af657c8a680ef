#pragma once

#include <optional>
#include <vector>

#include <opencv2/core.hpp>

namespace cotton_harvester {
namespace perception {

/// A boll's disc in the image, fitted to the part of its outline that is its own silhouette.
struct BollCircle {
  cv::Point2d centre;      ///< [px]
  double radius_px = 0.0;  ///< [px]
  double rms_px = 0.0;     ///< RMS distance of the fitted outline points from the circle [px]
  /// Angle around the centre covered by runs of fitted points at most 4 px of arc apart [rad], up to 2 pi.
  double arc_coverage_rad = 0.0;
  int points = 0;  ///< outline points used [-]
};

/// Fits a circle to the OUTER part of a region's outline: the outline points that lie on the region's convex hull
/// (within hull_tolerance_px). A leaf, a branch, the image border or another boll that hides part of a boll cuts
/// into its silhouette from outside, so the cut runs inside the hull (only its two ends touch it) while the boll's
/// own edge is the hull; the circle through the hull points is the whole boll's, wherever the visible centroid
/// lies. outline: the region's contour [px], dense (every boundary pixel, as cv::CHAIN_APPROX_NONE gives it).
/// The radius is that of the boundary pixels' outer edge (half a pixel beyond their centres).
/// std::nullopt for fewer than 5 usable points or a degenerate (collinear) set.
std::optional<BollCircle> fitOuterCircle(const std::vector<cv::Point>& outline, double hull_tolerance_px = 1.0);

/// Least-squares (algebraic, Kasa) circle through points; std::nullopt for fewer than 3 or collinear points.
std::optional<BollCircle> fitCircle(const std::vector<cv::Point2d>& points);

}  // namespace perception
}  // namespace cotton_harvester
