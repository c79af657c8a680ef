#pragma once

#include <vector>

#include <opencv2/core.hpp>

namespace cotton_harvester {
namespace perception {

/// One boll found in an image, before it is located in 3D.
struct BollDetection {
  cv::Rect2d box;           ///< bounding box [px]
  cv::Point2d centroid;     ///< image centroid [px]
  double confidence = 0.0;  ///< detector score [0, 1]
};

/// Finds cotton bolls in a colour image. Implementations: ColourBollDetector (default), DarknetBollDetector.
class BollDetector {
 public:
  virtual ~BollDetector() = default;

  /// bgr: 8-bit 3-channel image. exclude: optional CV_8U mask of the same size whose non-zero pixels cannot be
  /// bolls (the segmented end-effector, paper Figure 10c); empty when unused.
  virtual std::vector<BollDetection> detect(const cv::Mat& bgr, const cv::Mat& exclude) = 0;
};

}  // namespace perception
}  // namespace cotton_harvester
