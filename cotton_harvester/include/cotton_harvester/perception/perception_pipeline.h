#pragma once

#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "cotton_harvester/perception/boll_detector.h"
#include "cotton_harvester/perception/boll_locator.h"
#include "cotton_harvester/perception/camera_model.h"
#include "cotton_harvester/perception/end_effector_detector.h"

namespace cotton_harvester {
namespace perception {

/// Which boll is "nearest" (the one to pick next).
enum class NearestBy {
  kCamera,       ///< smallest range from the lens (paper Algorithm 1, step 6); the default
  kEndEffector,  ///< smallest 3D distance from the end-effector when it is located, else from the lens
};

std::optional<NearestBy> parseNearestBy(const std::string& name);
std::string toString(NearestBy nearest_by);

/// Everything the per-frame pipeline needs besides the boll detector.
struct PerceptionParams {
  CameraIntrinsics intrinsics;
  EndEffectorParams end_effector;
  LocatorParams locator;
  ReachParams reach;
  BollGeometry geometry;  ///< boll sizes and heights: the detector's pixel thresholds and the 3D plausibility test
  /// Drop detections on the ground (below half the lowest boll's height over the cloud's ground) or of a size no
  /// boll has at their measured depth. Off only for scenes without a ground, e.g. a flat test cloud.
  bool check_plausibility = true;
  /// With check_plausibility: a boll is a rounded cluster of lint lobes whose visible surface bulges towards the
  /// camera (a sphere's white cap seen from above: its rim about 0.5 of its radius deeper than its centre), while a
  /// label, a flat fold of a bag or a bar is flat in whatever plane it lies. A detection located from its visible
  /// surface (a detector that estimates the disc) is dropped when its dome (LocatedPoint::dome_m, tilt taken out)
  /// plus boll_dome_sigmas of its standard error is below this share of its radius at its depth. Detections whose
  /// dome could not be measured are kept. 0: off [0, 1].
  double boll_min_dome_fraction = 0.2;
  /// A dome that is this many standard errors short of boll_min_dome_fraction is flat; a noisier one (a small or
  /// distant boll, few valid points) is kept [-] (>= 0).
  double boll_dome_sigmas = 1.0;
  NearestBy nearest_by = NearestBy::kCamera;
  /// Detections without depth (too few valid cloud points under them) are located from their image radius, the
  /// typical boll radius and the camera's height (locateBySize) and marked BollDepthSource::kImageSize, instead of
  /// being dropped. Off by default: such a point is only good to +-(boll_radius_max_m - boll_radius_min_m) /
  /// (2 boll_radius_typical_m) of its range.
  bool size_fallback = false;
  /// How far behind the visible surface point a boll's centre lies, in boll radii (LocatedBoll::centre): 1 for a
  /// sphere; a boll whose lint stands lower than it is wide (the datasheet world's core and lobes: 0.6) less [0, 1].
  double boll_top_fraction = 1.0;
};

/// Returns an empty string when valid, otherwise every bad field.
std::string validate(const PerceptionParams& params);

/// Where a located boll's depth came from.
enum class BollDepthSource {
  kSurface,    ///< the cloud points of its visible surface under its outline (locateBollSurface)
  kWindow,     ///< the cloud window around its image centroid (locate)
  kImageSize,  ///< no depth: its image radius, the typical boll radius and the camera height (locateBySize)
};

std::string toString(BollDepthSource source);

/// A boll located in 3D. The 3D convention: `position` is the boll's VISIBLE SURFACE point nearest the camera on the
/// ray through its centre (what the cloud measures; the arm's nozzle goes there); `centre` is the boll's centre, one
/// boll radius (radius_m) deeper along the same ray.
struct LocatedBoll {
  BollDetection detection;
  cv::Point3d position;  ///< visible surface point, camera frame [m]
  double range_m = 0.0;  ///< eq. 6 of `position` [m]
  /// The boll's centre: position + boll_top_fraction * radius_m along the unit ray through position, camera frame
  /// [m].
  cv::Point3d centre;
  /// The boll's radius used for `centre` [m]: from its image radius (the disc's, or half the box's mean side) at its
  /// range, clamped to the geometry's boll radii; the typical radius with kImageSize.
  double radius_m = 0.0;
  BollDepthSource depth_source = BollDepthSource::kSurface;
  int valid_points = 0;  ///< valid cloud points its depth came from (0 with kImageSize) [-]
  bool reachable = false;
  /// LocatedPoint::dome_m and dome_sigma_m (NaN: not measured) [m].
  double dome_m = std::numeric_limits<double>::quiet_NaN();
  double dome_sigma_m = std::numeric_limits<double>::quiet_NaN();
};

/// Where the arm's own position sensing (stepper counters and the arm's calibration) puts the end-effector. With it
/// the pipeline searches for the housing only where the arm can be and takes, among the orange regions there, the
/// one whose 3D position agrees with it and whose size fits the housing at its depth, instead of the largest orange
/// region of the whole image (terracotta pots and other orange-brown things pass the colour test).
struct EndEffectorPrior {
  cv::Point3d position;          ///< centre of the housing's top face, camera frame [m] (z > 0)
  double radius_m = 0.08;        ///< perception's end-effector is taken only this close to it [m] (> 0)
  double housing_half_m = 0.05;  ///< half side of the housing's top face [m] (> 0): its image size at its depth
};

/// Empty when the prior can be used, otherwise what is wrong with it.
std::string validate(const EndEffectorPrior& prior);

/// Why a frame gave no result.
enum class FrameStatus {
  kOk,
  kEmptyImage,    ///< zero-sized image
  kBadImage,      ///< not 8-bit 3-channel
  kSizeMismatch,  ///< image size differs from the intrinsics' width x height
  kNoDepth,       ///< cloud missing or not the image's size: nothing can be located
};

std::string toString(FrameStatus status);

/// What one frame shows.
struct FrameResult {
  FrameStatus status = FrameStatus::kOk;
  std::vector<LocatedBoll> bolls;  ///< located bolls (those without depth are left out and counted)
  int nearest_reachable = -1;      ///< index into bolls, -1 if none
  int bolls_detected = 0;          ///< 2D detections before 3D location
  int bolls_without_depth = 0;     ///< detections dropped for lack of valid cloud points
  int bolls_implausible = 0;       ///< detections dropped in 3D: on the ground or of a size no boll has
  int bolls_size_fallback = 0;     ///< bolls in `bolls` located by their image size (BollDepthSource::kImageSize)
  /// The detections that were dropped, and why (for scoring where a detected boll is lost).
  struct Dropped {
    BollDetection detection;
    bool no_depth = false;  ///< true: too few valid cloud points; false: implausible in 3D (ground, size or dome)
    cv::Point3d position;   ///< where it was located when implausible [m]
  };
  std::vector<Dropped> dropped;
  std::optional<EndEffectorObservation> end_effector_image;  ///< end-effector in the image
  std::optional<LocatedPoint> end_effector;                  ///< end-effector in 3D, when its depth is known
  cv::Mat end_effector_mask;  ///< CV_8U, 255 on the segmented end-effector (empty when not found)
  cv::Mat boll_exclusion;     ///< CV_8U, 255 where bolls are not searched: end-effector and arm (empty: none)
  /// With an EndEffectorPrior: orange regions found where the arm can be, and those of them refused (too far in
  /// 3D from the prior, no depth, or larger than the housing at their depth).
  int end_effector_candidates = 0;
  int end_effector_candidates_refused = 0;
};

/// The centre of a boll whose visible surface point nearest the camera is `surface` [m] and whose radius is radius_m:
/// radius_m further along the ray through `surface`.
cv::Point3d centreBehindSurface(const cv::Point3d& surface, double radius_m);

/// The size fallback: a boll seen with image radius radius_px [px] at `pixel`, with no depth. Its centre range is
/// where a boll of the typical radius has that image radius, clamped to where boll centres can be (between
/// boll_height_min_m and boll_height_max_m above a ground camera_height_m below the camera; ground_depth_m instead of
/// camera_height_m when finite). Returns the located boll with position = its surface point, centre, radius_m =
/// the typical radius, depth_source kImageSize; std::nullopt when radius_px <= 0 or the pixel is not finite.
std::optional<LocatedBoll> locateBySize(const BollDetection& detection, const CameraIntrinsics& intrinsics,
                                        const BollGeometry& geometry, double ground_depth_m, DepthModel model);

/// A box detection (no disc estimated) located from the visible surface under the disc inscribed in its box (0.8 of
/// half its mean side around the box's centre; locateBollSurface): used when the window at its centroid has too few
/// valid points. std::nullopt as locateBollSurface.
std::optional<LocatedPoint> locateBoxDisc(const cv::Mat& cloud, const BollDetection& detection,
                                          const CameraIntrinsics& intrinsics, const LocatorParams& params);

/// The image radius of a detection [px]: its disc's when estimated, else half the mean side of its box.
double imageRadiusPx(const BollDetection& detection);

/// Step 6 of Algorithm 1: the index of the nearest reachable boll (-1: none reachable). Nearest by range from the
/// lens, or with NearestBy::kEndEffector and a located end-effector by 3D distance from it; the first of equals.
int nearestReachable(const std::vector<LocatedBoll>& bolls, const std::optional<LocatedPoint>& end_effector,
                     NearestBy nearest_by);

/// Algorithm 1 up to step 7: end-effector by colour (its depth: the median over its segmented region), bolls by
/// the detector (the end-effector's region and the arm masked out: the band from the end-effector to the arm's
/// base, at the arm's depth), each boll centroid located in the organised cloud, detections on the ground or of
/// implausible size dropped, reachability, and the nearest reachable boll.
class PerceptionPipeline {
 public:
  /// Throws std::invalid_argument on bad parameters or a null detector.
  PerceptionPipeline(const PerceptionParams& params, std::unique_ptr<BollDetector> detector);

  /// bgr: 8-bit colour image; cloud: CV_32FC3 organised cloud of the same size (camera frame [m], NaN holes).
  FrameResult process(const cv::Mat& bgr, const cv::Mat& cloud);
  /// As above, with the end-effector searched only near `prior` (see EndEffectorPrior). An invalid prior (NaN,
  /// z <= 0) is ignored: the whole image is searched.
  FrameResult process(const cv::Mat& bgr, const cv::Mat& cloud, const std::optional<EndEffectorPrior>& prior);

  const PerceptionParams& params() const { return params_; }

  /// Replaces the intrinsics (e.g. from camera_info). Throws std::invalid_argument when they are invalid.
  void setIntrinsics(const CameraIntrinsics& intrinsics);

 private:
  void applyGeometry();
  /// kOk when the image is 8-bit colour of the intrinsics' size, else why not.
  FrameStatus checkImage(const cv::Mat& bgr) const;
  /// Steps 1-3 up to the boll search: the end-effector (near the prior when it is usable, else in the whole image),
  /// its depth, and the region where bolls are not searched (the housing and the arm).
  void findEndEffectorAndArm(const cv::Mat& bgr, const cv::Mat& cloud, bool has_depth,
                             const std::optional<EndEffectorPrior>& prior, FrameResult* result) const;
  /// Steps 4, 5 and 7: each detection located in the cloud, implausible ones dropped, reachability; the counts.
  void locateBolls(const std::vector<BollDetection>& detections, const cv::Mat& cloud, FrameResult* result) const;
  bool plausible(const BollDetection& detection, const LocatedPoint& located, double ground_depth_m) const;
  /// The end-effector near the prior: fills end_effector_image, end_effector, end_effector_mask and the counts.
  void findEndEffectorNear(const cv::Mat& bgr, const cv::Mat& cloud, const EndEffectorPrior& prior,
                           FrameResult* result) const;

  PerceptionParams params_;
  EndEffectorDetector end_effector_detector_;
  std::unique_ptr<BollDetector> detector_;
};

}  // namespace perception
}  // namespace cotton_harvester
