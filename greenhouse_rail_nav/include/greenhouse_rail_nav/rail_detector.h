#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "greenhouse_rail_nav/cloud_projection.h"
#include "greenhouse_rail_nav/depth_camera.h"
#include "greenhouse_rail_nav/rail_detector_params.h"
#include "greenhouse_rail_nav/rail_pair.h"

namespace greenhouse_rail_nav {

/// Outcome of one detection.
struct RailDetection {
  /// kFoundXUnobserved: rails found, y and yaw valid, but their start is out of the camera's view (the
  /// robot is too close or turned): x is then where the rails enter the image, and the true start is
  /// nearer the robot (x in the rail frame is at least the reported one).
  enum class Status { kFound, kFoundXUnobserved, kNotFound, kBadInput };
  Status status = Status::kNotFound;
  std::string reason;                  ///< why not found / rejected, or a summary when found
  thorvald_base::Pose2D rail_in_base;  ///< the rail frame in base_link (after the mount correction)
  thorvald_base::Pose2D base_in_rail;  ///< base_link in the rail frame: the paper's output
  std::array<double, 3> variance{};    ///< x [m^2], y [m^2], yaw [rad^2] of base_in_rail
  double fit_score = 0.0;              ///< linearity of the chosen line
  double gauge_m = 0.0;                ///< measured gauge [m]
  std::size_t finite_points = 0, points_in_band = 0, clusters = 0, lines = 0;
  std::vector<RailLine> rails;  ///< the two rails (base_link, after the mount correction)

  /// Rails found (x may be unobserved).
  bool found() const { return status == Status::kFound || status == Status::kFoundXUnobserved; }
  bool xObserved() const { return status == Status::kFound; }
};

enum class RailFitMethod {
  kClusterLines,   ///< the paper: Euclidean clusters, least-squares line per cluster, best r, partner
  kRansacBaseline  ///< baseline: sequential PCL RANSAC lines on the same cropped cloud
};

/// Finds the rail set in front of the robot in one organised depth cloud.
class RailDetector {
 public:
  explicit RailDetector(const RailDetectorParams& params) : params_(params) {}

  /// camera_in_base: the cloud's frame in base_link. mount_correction: a planar correction applied to
  /// everything seen in base_link (from the calibration; identity if none).
  RailDetection detect(const OrganisedCloud& cloud, const Eigen::Isometry3d& camera_in_base,
                       const thorvald_base::Pose2D& mount_correction = thorvald_base::Pose2D(),
                       RailFitMethod method = RailFitMethod::kClusterLines) const;

  /// Step 1 alone: finite points moved to base_link and cropped to the rails' band, thinned to voxels.
  /// floor_cells, if given, receives a grid of 5 cm cells over the crop region (rows along x from
  /// crop_x_min_m, columns along y from -crop_y_max_m): 1 where a floor point was seen, 0 elsewhere.
  /// raw_band, if given, receives the cropped points before thinning.
  std::vector<Eigen::Vector3f> cropToRailBand(const OrganisedCloud& cloud, const Eigen::Isometry3d& camera_in_base,
                                              std::size_t* finite_points, std::vector<float>* floor_cells = nullptr,
                                              std::vector<Eigen::Vector3f>* raw_band = nullptr) const;

  const RailDetectorParams& params() const { return params_; }

 private:
  /// Steps 1-5 on `searched` (the depth points, or the holes laid on the pipes' height); the floor grid is filled
  /// from the depth points when `searched` is `depth` and reused otherwise.
  RailDetection search(const OrganisedCloud& searched, const OrganisedCloud& depth,
                       const std::optional<CloudProjection>& projection, const Eigen::Isometry3d& camera_in_base,
                       const thorvald_base::Pose2D& mount_correction, RailFitMethod method,
                       std::vector<float>* floor_cells) const;

  RailDetectorParams params_;
};

}  // namespace greenhouse_rail_nav
