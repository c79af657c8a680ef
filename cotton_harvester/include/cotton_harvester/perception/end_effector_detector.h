#pragma once

#include <optional>
#include <string>

#include <opencv2/core.hpp>

namespace cotton_harvester {
namespace perception {

/// Which image point stands for the end-effector.
enum class EndEffectorPoint {
  kCentroid,  ///< centroid of the largest orange region (default)
  kTip,       ///< the region's extreme point along tip_direction (the front of the end-effector, paper §2.8)
};

/// Thresholds of the paper's §2.6 colour segmentation. Defaults: R 200-255, G 0-255, B 0-60.
struct EndEffectorParams {
  int r_min = 200, r_max = 255;  ///< red channel window [0, 255]
  int g_min = 0, g_max = 255;    ///< green channel window [0, 255]
  int b_min = 0, b_max = 60;     ///< blue channel window [0, 255]
  /// Regions smaller than this are dropped (the paper's M, "the number of pixels defining the smallest boll")
  /// [px].
  int min_area_px = 150;
  /// Side of the square morphological opening that removes speckle before contours are traced [px]; 0 or 1:
  /// none.
  int opening_px = 3;
  EndEffectorPoint point = EndEffectorPoint::kCentroid;
  /// Image direction of the tip when point == kTip: unit vector in (u, v) [-]. Default: towards +u.
  cv::Point2d tip_direction{1.0, 0.0};
  /// Image direction from the end-effector along the horizontal arm to its base, (u, v) [-]; (0, 0): do not mask
  /// the arm. The arm (bright aluminium) is masked out of the boll search as a band as wide as the end-effector's
  /// bounding box across that direction (paper §2.6: bolls are searched after segmenting the arm).
  cv::Point2d arm_direction{-1.0, 0.0};
};

/// Returns an empty string when valid, otherwise the bad field and what was expected.
std::string validate(const EndEffectorParams& params);

/// The end-effector as found in one image.
struct EndEffectorObservation {
  cv::Point2d pixel;     ///< image position (centroid or tip) [px]
  cv::Rect box;          ///< bounding box of the region [px]
  double area_px = 0.0;  ///< contour area [px^2]
};

/// Finds the orange end-effector: RGB threshold, background removal (everything outside the mask), opening,
/// contours below min_area_px dropped, the largest remaining region is the end-effector.
/// The band of the image the horizontal arm can occupy: from the end-effector's point along arm_direction to the
/// image border, as wide as its bounding box across that direction. CV_8U of `size`, 255 inside; all zero when
/// arm_direction is (0, 0).
cv::Mat armBandMask(const cv::Size& size, const EndEffectorObservation& observation, const EndEffectorParams& params);

class EndEffectorDetector {
 public:
  explicit EndEffectorDetector(const EndEffectorParams& params);

  /// bgr: 8-bit 3-channel image. mask_out (optional): receives the segmented end-effector region (CV_8U,
  /// 255 inside), empty when nothing is found. Returns std::nullopt when no region is large enough.
  std::optional<EndEffectorObservation> detect(const cv::Mat& bgr, cv::Mat* mask_out = nullptr) const;

  const EndEffectorParams& params() const { return params_; }

 private:
  EndEffectorParams params_;
};

}  // namespace perception
}  // namespace cotton_harvester
