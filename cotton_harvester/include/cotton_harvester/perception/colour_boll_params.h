#pragma once

#include <string>

namespace cotton_harvester {
namespace perception {

/// Thresholds of the colour and shape boll segmenter: open bolls are white (low saturation), bright and
/// compact. Sizes are not in pixels: they follow from the BollGeometry and the focal length (setGeometry), so the
/// same parameters hold at 640x360 and at 1920x1080, and at another camera height.
struct ColourBollParams {
  int value_min = 150;      ///< minimum HSV value (brightness) of boll pixels in a well exposed image [0, 255]
  int saturation_max = 70;  ///< maximum HSV saturation of boll pixels [0, 255]
  /// Exposure and shade: the value threshold drops to value_contrast times the scene's median value (soil and
  /// leaves; open bolls reflect about twice as much), but not below value_floor.
  double value_contrast = 1.35;       ///< [-]
  int value_floor = 60;               ///< [0, 255]
  double opening_fraction = 0.45;     ///< side of the speckle-removing opening as a share of the smallest boll
                                      ///< radius in pixels [-]; a side <= 1 px: no opening
  double closing_fraction = 1.0;      ///< side of the closing that joins a boll cut by a twig, same unit [-]
  double min_visible_fraction = 0.4;  ///< smallest region: this share of the smallest boll's disc [0, 1]
  int max_cluster_bolls = 8;          ///< largest region split into bolls, in largest-boll discs [-]
  double min_circularity = 0.45;      ///< single bolls: 4 pi area / perimeter^2 [0, 1]
  double min_solidity = 0.80;         ///< single bolls: area / convex hull area [0, 1]
  double max_aspect_ratio = 2.5;      ///< long side / short side of the smallest rotated rectangle [-]
  /// Touching bolls are split where the region narrows: two maxima of the distance transform are two bolls when
  /// the region's half width between them drops below this share of the smaller one's inscribed radius [0, 1].
  double split_neck_ratio = 0.75;
  /// A single region that fails the shape tests but covers at least partial_min_fraction of the smallest boll's
  /// disc and fits inside the largest boll's disc is reported as a partial detection (BollDetection::partial,
  /// confidence scaled by 0.3) instead of dropped: a boll seen past a leaf, for a picker that can push the leaf aside
  /// and look again. 0: off (the default; in an open field a pale crescent is as likely to be glare on a leaf).
  double partial_min_fraction = 0.0;
  /// A boll partly hidden by a leaf, a branch or the image border: a region that fails the whole-boll shape tests is
  /// still a boll when its own silhouette (the outline on its convex hull, fitOuterCircle) is a circular arc (RMS
  /// distance at most circle_max_rms_fraction of the radius, covering at least circle_min_arc_deg), the circle's
  /// radius is a boll's at some allowed height, and the region covers at least this share of that circle's disc.
  /// Reported with BollDetection::partial set and its full confidence. 0: off [0, 1].
  double partial_min_visible = 0.35;
  double circle_max_rms_fraction = 0.08;  ///< [-]
  double circle_min_arc_deg = 135.0;      ///< [deg]
  /// true: a region that passes the whole-boll shape tests must also show a boll's arc (as above), which refuses
  /// straight-sided white things (labels, pieces of a bar) but also sunlit bolls whose lobes and shading make their
  /// outline ragged (recall drops by several points on perception_bench's sunny frames). false: the shape tests alone.
  bool whole_needs_arc = false;
};

/// Returns an empty string when valid, otherwise the bad field and what was expected.
std::string validate(const ColourBollParams& params);

/// The pixel thresholds the detector derives from its parameters, the geometry and the focal length.
struct ColourBollScale {
  double radius_min_px = 0.0;        ///< smallest boll [px]
  double radius_max_px = 0.0;        ///< largest boll [px]
  double min_area_px = 0.0;          ///< smallest region kept [px^2]
  double partial_min_area_px = 0.0;  ///< smallest region reported as a partial boll [px^2]
  double max_single_area_px = 0.0;   ///< largest region taken as one boll without a split [px^2]
  double max_area_px = 0.0;          ///< largest region considered at all [px^2]
  int opening_px = 0;                ///< side of the opening [px]
  int closing_px = 0;                ///< side of the closing [px]
};

/// Share of its disc that a whole boll's white lint covers: about 0.88 (the outer 6 % of its radius are brown
/// bracts), a little less with the creases between its lobes. A boll showing less is partly hidden.
constexpr double kWholeWhiteShare = 0.75;

}  // namespace perception
}  // namespace cotton_harvester
