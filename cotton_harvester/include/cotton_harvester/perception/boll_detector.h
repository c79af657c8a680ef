#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "cotton_harvester/perception/camera_model.h"

namespace cotton_harvester {
namespace perception {

/// One boll found in an image, before it is located in 3D.
struct BollDetection {
  cv::Rect2d box;           ///< bounding box [px]
  cv::Point2d centroid;     ///< image centroid [px]
  double confidence = 0.0;  ///< detector score [0, 1]
  /// Only part of a boll: a white region that fails the whole-boll shape tests (a leaf over it leaves a crescent);
  /// its centroid lies off the boll's centre towards the visible part.
  bool partial = false;
  /// The whole boll's disc as estimated from what is visible: centre [px] and radius [px] of a circle fitted to the
  /// region's own silhouette (ColourBollDetector; see fitOuterCircle). radius_px 0: not estimated (box detectors);
  /// then centre is unused and the pipeline locates the centroid.
  cv::Point2d centre;
  double radius_px = 0.0;
  /// The visible region's outline in image pixels (empty for box detectors): the pipeline reads the boll's depth from
  /// the cloud points under it.
  std::vector<cv::Point> outline;
};

/// Where bolls can be and how large they are: the size thresholds of the detectors follow from these and the focal
/// length, so they hold at any image size and camera height.
struct BollGeometry {
  double camera_height_m = 2.20;    ///< camera above the ground (paper §2.1) [m]
  double boll_radius_min_m = 0.02;  ///< smallest open boll [m]
  double boll_radius_max_m = 0.05;  ///< largest open boll [m]
  /// A typical open boll [m], in [min, max]: the size fallback's ranging (PerceptionParams::size_fallback).
  double boll_radius_typical_m = 0.035;
  double boll_height_min_m = 0.15;  ///< lowest boll centre above the ground [m]
  double boll_height_max_m = 1.30;  ///< highest boll centre above the ground [m]
};

/// Returns an empty string when valid, otherwise the bad field and what was expected.
std::string validate(const BollGeometry& geometry);

/// Projected boll radius range [px] for a focal length [px]: the smallest boll at the lowest height, the largest
/// at the highest.
struct PixelRadiusRange {
  double min_px = 0.0;
  double max_px = 0.0;
};
PixelRadiusRange bollRadiusPx(const BollGeometry& geometry, double focal_px);

/// Finds cotton bolls in a colour image. Implementations: ColourBollDetector (default), DarknetBollDetector.
class BollDetector {
 public:
  virtual ~BollDetector() = default;

  /// bgr: 8-bit 3-channel image. exclude: optional CV_8U mask of the same size whose non-zero pixels cannot be
  /// bolls (the segmented end-effector, paper Figure 10c); empty when unused.
  virtual std::vector<BollDetection> detect(const cv::Mat& bgr, const cv::Mat& exclude) = 0;

  /// The camera and the boll geometry the size thresholds follow. Called by the pipeline at start and whenever the
  /// intrinsics change; detectors without size thresholds ignore it.
  virtual void setGeometry(const CameraIntrinsics& /*intrinsics*/, const BollGeometry& /*geometry*/) {}
};

}  // namespace perception
}  // namespace cotton_harvester
