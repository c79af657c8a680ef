#pragma once

#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "cotton_harvester/perception/boll_circle.h"

namespace cotton_harvester {
namespace perception {

/// What makes a circle fitted to a region's outline a boll's: round and of a boll's size.
struct BollCircleLimits {
  double max_rms_fraction = 0.08;  ///< RMS distance of the outline points at most this share of the radius [-]
  double min_arc_deg = 135.0;      ///< the fitted points cover at least this arc [deg]
  double radius_min_px = 0.0;      ///< smallest boll [px]: circles down to 0.7 of it pass
  double radius_max_px = 0.0;      ///< largest boll [px]: circles up to 1.2 times it pass
};

/// Whether the circle is round (RMS within max_rms_fraction of its radius or 0.75 px, covering min_arc_deg) and of a
/// boll's radius at some allowed height (the white part of a boll ends a little inside its silhouette).
bool isBollCircle(const BollCircle& circle, const BollCircleLimits& limits);

/// Whether the circle holds the disc (centre, radius) [px], within a pixel's slack (or a tenth of its radius).
bool holdsDisc(const BollCircle& circle, const cv::Point2d& centre, double radius);

/// The circle of an outline's own silhouette (fitOuterCircle) when it is a boll's (isBollCircle), else std::nullopt.
std::optional<BollCircle> roundOutline(const std::vector<cv::Point>& outline, const BollCircleLimits& limits);

/// Outline points that can be the silhouette of a boll whose disc holds the inscribed disc (centre, radius): a disc
/// that holds it has its outline between radius and about twice the boll's radius minus it from the centre, and a
/// circle's outline runs across the direction to any point inside it, most nearly so for one that lies near its
/// centre. Kept: points within 1.6 radii (a boll's own disc is at most about 1.3 times the inscribed one when most
/// of it is visible) whose outline runs within 30 degrees of across that direction; the outline of another boll
/// beside it or of a thin thing joined to it runs along it.
std::vector<cv::Point2d> lobeOutline(const std::vector<cv::Point>& outline, const cv::Point2d& centre, double radius);

/// The circle of a boll whose disc holds the inscribed disc (centre, radius) of a region, fitted to the part of the
/// region's outline that runs around that disc (lobeOutline, refitted three times on the points near the circle),
/// when it is a boll's (isBollCircle) and holds the disc; else std::nullopt.
std::optional<BollCircle> lobeCircle(const std::vector<cv::Point>& outline, const cv::Point2d& centre, double radius,
                                     const BollCircleLimits& limits);

}  // namespace perception
}  // namespace cotton_harvester
