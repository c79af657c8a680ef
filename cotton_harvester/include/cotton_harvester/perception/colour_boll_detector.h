#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cotton_harvester/perception/boll_circle_fit.h"
#include "cotton_harvester/perception/boll_detector.h"
#include "cotton_harvester/perception/boll_region.h"
#include "cotton_harvester/perception/colour_boll_params.h"

namespace cotton_harvester {
namespace perception {

/// The lint-coloured pixels of an 8-bit BGR image: HSV value (the largest channel) at least value_min and HSV
/// saturation at most saturation_max (both [0, 255]), tested exactly on the integers: 255 (V - min) <=
/// saturation_max V. CV_8U, 255 on such pixels, else 0. Throws cv::Exception for another image type.
cv::Mat whitePixels(const cv::Mat& bgr, int value_min, int saturation_max);

/// The default detector: HSV threshold for white and bright, opening, closing, external contours (the region mask:
/// cutBollRegion, findBollPeaks); each region's distance
/// transform maxima that are separated by a neck are touching bolls and the region is split between them (each
/// pixel to the nearest maximum, relative to its inscribed radius; a part's circle is that of its own outline when it
/// holds the part's inscribed disc); single regions pass shape tests (area, circularity, solidity, aspect ratio) or,
/// when their outline is no circle, give up the boll on their maximum's own circle (peelBoll). Confidence grows with
/// circularity, solidity and brightness (boll_shape.h). The stages live in boll_region.h, boll_shape.h,
/// boll_circle_fit.h, touching_bolls.h and boll_peeling.h; this class chains them.
class ColourBollDetector : public BollDetector {
 public:
  /// Throws std::invalid_argument on bad parameters. Until setGeometry, the paper's camera at 1280x720 and the
  /// default BollGeometry set the sizes.
  explicit ColourBollDetector(const ColourBollParams& params);

  std::vector<BollDetection> detect(const cv::Mat& bgr, const cv::Mat& exclude) override;
  void setGeometry(const CameraIntrinsics& intrinsics, const BollGeometry& geometry) override;

  const ColourBollScale& scale() const { return scale_; }

 private:
  int valueThreshold(const cv::Mat& bgr) const;
  /// The limits of a boll's circle at the current scale.
  BollCircleLimits circleLimits() const;
  /// Least share of its disc that a boll's visible part must cover (partial_min_visible; a whole boll's when 0).
  double visibleShareMin() const;
  /// Bolls in one region (an external contour of the mask): split between its distance-transform peaks when it has
  /// several (splitTouchingBolls), else looked at as one (detectSingle). peels_left: how many more times a boll may be
  /// taken out of a region that is not one round boll (peelBoll), the rest looked at again.
  void detectRegion(const std::vector<cv::Point>& contour, const cv::Mat& bgr, const cv::Mat& mask, int peels_left,
                    std::vector<BollDetection>* bolls) const;
  /// A region with at most one peak (area: its contour's [px^2]): one whole boll (the shape tests), a boll partly
  /// hidden (its silhouette is a boll's circle, partial_min_visible), a boll peeled off something joined to it
  /// (peelBoll), a part of a boll (partial_min_fraction), or nothing.
  void detectSingle(const std::vector<cv::Point>& contour, double area, const BollRegion& region,
                    const std::vector<BollPeak>& peaks, const cv::Mat& bgr, const cv::Mat& mask, int peels_left,
                    std::vector<BollDetection>* bolls) const;
  /// The boll on the lobeCircle of the region's distance-transform maximum (peak, peak_radius; image pixels): the
  /// region's pixels on its disc (discBoll), when the region crosses the circle only through a neck
  /// (rimCrossingHalfWidth within split_neck_ratio of the radius) and they cover visibleShareMin of it; what lies off
  /// the disc (restOffDisc) goes through detectRegion again. false: no such boll (nothing is added).
  bool peelBoll(const std::vector<cv::Point>& contour, const BollRegion& region, const cv::Point2d& peak,
                double peak_radius, const cv::Mat& bgr, const cv::Mat& mask, int peels_left,
                std::vector<BollDetection>* bolls) const;

  ColourBollParams params_;
  ColourBollScale scale_;
};

}  // namespace perception
}  // namespace cotton_harvester
