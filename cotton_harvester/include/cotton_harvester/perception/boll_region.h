#pragma once

#include <vector>

#include <opencv2/core.hpp>

namespace cotton_harvester {
namespace perception {

/// A maximum of a region's distance transform: the centre and radius of a disc inscribed in the region.
struct BollPeak {
  cv::Point2f centre;   ///< region-local pixel
  float radius = 0.0f;  ///< [px]
};

/// One region of the boll mask (an external contour) cut out on its own, as the colour detector's later stages look
/// at it: filled, with a margin so that the distance transform sees its edge everywhere.
struct BollRegion {
  cv::Rect box;             ///< the contour's bounding box in the image [px]
  double brightness = 0.0;  ///< the largest mean channel of the mask's pixels in the box [0, 1]
  int pad = 0;              ///< margin of `pixels` around the box on every side [px]
  cv::Point origin;         ///< image pixel of the (0, 0) of `pixels` and `dist`
  cv::Mat pixels;           ///< CV_8U: 255 inside the contour, 0 elsewhere
  /// CV_32F: distance [px] of each pixel of `pixels`, closed first (which fills the dark creases between a boll's
  /// lobes that would otherwise make one boll look like several), to the nearest pixel outside.
  cv::Mat dist;
};

/// Cuts the region of `contour` (image pixels, an external contour of `mask`) out of the 8-bit BGR image and its
/// CV_8U mask. radius_min_px: the smallest boll's radius; the closing before the distance transform is 0.7 of it
/// (odd, at least 3 px) and the margin a pixel more.
BollRegion cutBollRegion(const std::vector<cv::Point>& contour, const cv::Mat& bgr, const cv::Mat& mask,
                         double radius_min_px);

/// Smallest distance-transform value on the segment between two points: the region's half width at its neck [px].
float neckBetween(const cv::Mat& dist, const cv::Point2f& a, const cv::Point2f& b);

/// Maxima of a CV_32F distance transform that stand for separate bolls: local maxima (over a window x window square)
/// at least min_radius deep, strongest first (at most 64 looked at), kept when they lie outside every kept disc
/// (0.8 of the sum of the radii) and a neck narrower than neck_ratio of the smaller radius separates them from every
/// kept one.
std::vector<BollPeak> findBollPeaks(const cv::Mat& dist, double min_radius, double neck_ratio, int window);

}  // namespace perception
}  // namespace cotton_harvester
