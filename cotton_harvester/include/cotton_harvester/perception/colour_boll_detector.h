#pragma once

#include <string>
#include <vector>

#include "cotton_harvester/perception/boll_detector.h"

namespace cotton_harvester {
namespace perception {

/// Thresholds of the colour and shape boll segmenter: open bolls are white (low saturation), bright and
/// compact.
struct ColourBollParams {
  int value_min = 150;            ///< minimum HSV value (brightness) of boll pixels [0, 255]
  int saturation_max = 70;        ///< maximum HSV saturation of boll pixels [0, 255]
  int opening_px = 3;             ///< square opening that removes speckle and thin highlights [px]; <= 1: none
  int min_area_px = 150;          ///< smallest boll region [px^2]
  int max_area_px = 20000;        ///< largest boll region [px^2]
  double min_circularity = 0.45;  ///< 4 pi area / perimeter^2 [0, 1]
  double min_solidity = 0.80;     ///< area / convex hull area [0, 1]
  double max_aspect_ratio = 2.5;  ///< long side / short side of the bounding box [-]
};

/// Returns an empty string when valid, otherwise the bad field and what was expected.
std::string validate(const ColourBollParams& params);

/// The default detector: HSV threshold for white and bright, opening, external contours, then shape tests
/// (area, circularity, solidity, aspect ratio). Confidence grows with circularity, solidity and brightness.
class ColourBollDetector : public BollDetector {
 public:
  explicit ColourBollDetector(const ColourBollParams& params);

  std::vector<BollDetection> detect(const cv::Mat& bgr, const cv::Mat& exclude) override;

 private:
  ColourBollParams params_;
};

}  // namespace perception
}  // namespace cotton_harvester
