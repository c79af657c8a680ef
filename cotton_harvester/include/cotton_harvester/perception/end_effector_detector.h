#pragma once

#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "cotton_harvester/perception/camera_model.h"

namespace cotton_harvester {
namespace perception {

/// Which image point stands for the end-effector.
enum class EndEffectorPoint {
  kCentroid,  ///< centroid of the largest orange region (default)
  kTip,       ///< the region's extreme point along tip_direction (the front of the end-effector, paper §2.8)
};

/// Colour space of the end-effector segmentation.
enum class EndEffectorColourSpace {
  kHsv,  ///< hue window, minimum saturation and value: holds under sun glare and exposure changes (default)
  kRgb,  ///< the paper's §2.6 channel windows (R 200-255, G 0-255, B 0-60); fails when sunlight raises blue
};

std::optional<EndEffectorColourSpace> parseEndEffectorColourSpace(const std::string& name);
std::string toString(EndEffectorColourSpace space);

/// Thresholds of the end-effector's colour segmentation.
struct EndEffectorParams {
  EndEffectorColourSpace colour_space = EndEffectorColourSpace::kHsv;
  /// kHsv: OpenCV hue [0, 180): hue_min > hue_max wraps through red (e.g. 175..25).
  int hue_min = 0, hue_max = 25;
  int saturation_min = 150;  ///< kHsv: orange stays saturated under glare; soil and stems stay below [0, 255]
  int value_min = 80;        ///< kHsv: minimum brightness [0, 255]
  /// kHsv, glare: sunlight reflected by the housing saturates the sensor and washes the orange out; pixels this
  /// bright (value >= glare_value_min) count with a saturation down to glare_saturation_min [0, 255].
  int glare_value_min = 235;
  int glare_saturation_min = 110;
  int r_min = 200, r_max = 255;  ///< kRgb: red channel window [0, 255]
  int g_min = 0, g_max = 255;    ///< kRgb: green channel window [0, 255]
  int b_min = 0, b_max = 60;     ///< kRgb: blue channel window [0, 255]
  /// Regions smaller than this are dropped (the paper's M, "the number of pixels defining the smallest boll") at
  /// the reference focal length; at another image size the area scales with (focal length / reference)^2 [px].
  int min_area_px = 150;
  double reference_focal_px = 699.936;  ///< focal length min_area_px is given for (the paper's 1280x720) [px]
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
  /// Where the arm ends: its base (the vertical axis' carriage) lies this far from the optical axis along
  /// arm_direction, in the camera frame [m]. With the end-effector's depth known, the band stops there; without
  /// it, the band runs to the image border.
  double arm_base_offset_m = 0.80;
  /// With depth, only band pixels within this distance of the end-effector's depth (or without depth) are the arm:
  /// a boll above or below the arm stays searchable [m].
  double arm_depth_tolerance_m = 0.08;
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

/// The arm where it really is: the band from the end-effector to the arm's base (arm_base_offset_m, projected at
/// the end-effector's depth), and within it only the pixels whose cloud depth is within arm_depth_tolerance_m of
/// the end-effector's top (or that have no depth). end_effector_position: camera frame [m], z > 0; cloud: CV_32FC3
/// of `size`, or empty to keep the whole band up to the base.
cv::Mat armMask(const cv::Size& size, const EndEffectorObservation& observation,
                const cv::Point3d& end_effector_position, const CameraIntrinsics& intrinsics, const cv::Mat& cloud,
                const EndEffectorParams& params);

class EndEffectorDetector {
 public:
  explicit EndEffectorDetector(const EndEffectorParams& params);

  /// bgr: 8-bit 3-channel image. mask_out (optional): receives the segmented end-effector region (CV_8U,
  /// 255 inside), empty when nothing is found. Returns std::nullopt when no region is large enough.
  std::optional<EndEffectorObservation> detect(const cv::Mat& bgr, cv::Mat* mask_out = nullptr) const;

  /// Every orange region of at least the minimum area inside `roi` (clipped to the image), at full resolution,
  /// largest first. masks_out (optional): one CV_8U mask of the image's size per region, 255 inside. Used when
  /// the arm's own position sensing says where the end-effector must be: the caller then chooses among the
  /// regions by their 3D position instead of taking the largest (a terracotta pot passes the colour test too).
  std::vector<EndEffectorObservation> candidates(const cv::Mat& bgr, const cv::Rect& roi,
                                                 std::vector<cv::Mat>* masks_out = nullptr) const;

  const EndEffectorParams& params() const { return params_; }
  /// Scales min_area_px to this focal length [px] (> 0).
  void setFocalLength(double focal_px);
  double minAreaPx() const { return min_area_px_; }

 private:
  cv::Mat colourMask(const cv::Mat& bgr) const;  ///< CV_8U, 255 where the colour is the end-effector's
  /// The segmentation of `roi` (colour, opening) and its outer contours in image coordinates.
  std::vector<std::vector<cv::Point>> regions(const cv::Mat& bgr, const cv::Rect& roi) const;
  EndEffectorObservation observationOf(const std::vector<cv::Point>& contour, double area_px) const;

  EndEffectorParams params_;
  double min_area_px_;
};

}  // namespace perception
}  // namespace cotton_harvester
