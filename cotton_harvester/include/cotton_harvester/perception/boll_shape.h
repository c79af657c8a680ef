#pragma once

#include <algorithm>
#include <vector>

#include <opencv2/core.hpp>

namespace cotton_harvester {
namespace perception {

/// Shape measures of one mask region that the whole-boll tests compare with their limits.
struct RegionShape {
  double circularity = 0.0;  ///< 4 pi area / perimeter^2, at most 1 [-]
  double solidity = 0.0;     ///< area / convex hull area [-]
  /// Long side / short side (at least 1 px) of the smallest rotated rectangle: a thin glint at 45 degrees has a
  /// square bounding box [-].
  double aspect = 0.0;
};

/// The shape of a region's contour (image pixels) whose area is area_px [px^2]; 0 measures for a degenerate one.
RegionShape measureRegionShape(const std::vector<cv::Point>& contour, double area_px);

/// Whether the shape is a whole boll's: round, solid and compact enough.
inline bool wholeBollShape(const RegionShape& shape, double min_circularity, double min_solidity,
                           double max_aspect_ratio) {
  return shape.circularity >= min_circularity && shape.solidity >= min_solidity && shape.aspect <= max_aspect_ratio;
}

// Confidences [0, 1] of the colour detector's bolls; brightness: the region's [0, 1].

/// A region that passes the whole-boll shape tests: round, solid and bright.
inline double wholeBollConfidence(const RegionShape& shape, double brightness) {
  return std::clamp(shape.circularity * shape.solidity * brightness, 0.0, 1.0);
}
/// A region reported only as a part of a boll (partial_min_fraction): a whole boll's confidence scaled by 0.3.
inline double glimpseConfidence(const RegionShape& shape, double brightness) {
  return std::clamp(shape.circularity * shape.solidity * brightness * 0.3, 0.0, 1.0);
}
/// A boll on its circle: the share of its disc that is seen (cover) times brightness.
inline double discCoverConfidence(double cover, double brightness) { return std::clamp(cover * brightness, 0.0, 1.0); }

}  // namespace perception
}  // namespace cotton_harvester
