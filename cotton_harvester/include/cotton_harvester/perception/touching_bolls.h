#pragma once

#include <climits>
#include <vector>

#include <opencv2/core.hpp>

#include "cotton_harvester/perception/boll_circle_fit.h"
#include "cotton_harvester/perception/boll_detector.h"
#include "cotton_harvester/perception/boll_region.h"

namespace cotton_harvester {
namespace perception {

/// The pixels of a region that the split gives to one peak: their count, sums and extent (region-local pixels).
struct BollPart {
  double count = 0.0, sum_u = 0.0, sum_v = 0.0;
  int u_min = INT_MAX, v_min = INT_MAX, u_max = -1, v_max = -1;
};

/// Gives each pixel of the region to the peak whose disc edge is nearest (distance to its centre minus its radius;
/// the first of a tie). owner (CV_8U, the size of region.pixels) receives 1 + the part's index on the region, 0
/// elsewhere. One part per peak, in the peaks' order.
std::vector<BollPart> assignToPeaks(const BollRegion& region, const std::vector<BollPeak>& peaks, cv::Mat* owner);

/// Limits of the bolls that a split region gives.
struct TouchingBollLimits {
  double min_area_px = 0.0;         ///< a part smaller than this is dropped [px^2]
  double max_single_area_px = 0.0;  ///< a part larger than this is dropped [px^2]
  double max_aspect_ratio = 2.5;    ///< of the part's bounding box [-]
  double visible_share_min = 0.0;   ///< a part's circle must be covered this much for its own circle to be used [-]
  BollCircleLimits circle;          ///< the part's own outline circle (roundOutline)
};

/// Touching bolls: the region split between its distance-transform peaks (assignToPeaks), a boll per part within the
/// limits. A part's circle is that of its own outline when that is round, holds the part's inscribed disc and is
/// covered visible_share_min by the part; else the inscribed disc (the distance transform's maximum: the boll's
/// centre when the boll is whole). A boll partly hidden behind its neighbour shows a crescent whose inscribed disc is
/// small and lies off the boll's centre, towards its visible rim, while the circle of its outer arc is the whole
/// boll's. Confidence: the part's fill of its inscribed disc (at most 1) times the region's brightness.
std::vector<BollDetection> splitTouchingBolls(const BollRegion& region, const std::vector<BollPeak>& peaks,
                                              const TouchingBollLimits& limits);

}  // namespace perception
}  // namespace cotton_harvester
