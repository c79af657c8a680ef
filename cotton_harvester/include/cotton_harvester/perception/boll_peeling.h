#pragma once

#include <optional>

#include <opencv2/core.hpp>

#include "cotton_harvester/perception/boll_circle.h"
#include "cotton_harvester/perception/boll_detector.h"

namespace cotton_harvester {
namespace perception {

// Taking one boll out of a region that is not one round boll (a boll joined to a glint, a label, the sliver of a boll
// behind it): the boll on its own circle, and the rest of the region to be looked at again. region: the region's
// pixels (CV_8U, 255 inside); origin: the image pixel of its (0, 0); circle: the boll's, in image pixels.

/// Half width [px] of the region where it crosses the ring just outside the boll's edge (1.5 px beyond the circle):
/// the half chord of the longest run of region pixels around the ring, the ring's radius when that run covers half
/// of it or more. What else the region holds is joined to a boll through a neck when this stays well under the boll's
/// radius; a region that goes on past the circle as wide as the boll (a crescent past a leaf, whose thick part holds
/// a smaller circle than its boll's; a long bag whose end is round) is not a boll with something joined to it.
double rimCrossingHalfWidth(const cv::Mat& region, const cv::Point& origin, const BollCircle& circle);

/// The boll on the circle: the region's pixels on its disc (sub-pixel centre and radius, half a pixel beyond the
/// circle), when they are at least min_area_px [px^2] and cover at least visible_share_min of the circle's disc;
/// else std::nullopt. Its outline is the largest outline of those pixels, its centre and radius the circle's, its
/// confidence the covered share (at most 1) times brightness [0, 1]; partial when the share is under
/// kWholeWhiteShare.
std::optional<BollDetection> discBoll(const cv::Mat& region, const cv::Point& origin, const BollCircle& circle,
                                      double brightness, double min_area_px, double visible_share_min);

/// The rest of the region off the boll's disc and a pixel beyond its edge (which mixes the boll with what borders
/// it), opened with an ellipse of opening_px (when above 1 px) to clean off the slivers that its rim leaves.
cv::Mat restOffDisc(const cv::Mat& region, const cv::Point& origin, const BollCircle& circle, int opening_px);

}  // namespace perception
}  // namespace cotton_harvester
