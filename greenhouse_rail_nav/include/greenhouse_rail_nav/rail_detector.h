#pragma once

#include <array>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "greenhouse_rail_nav/depth_camera.h"
#include "greenhouse_rail_nav/rail_pair.h"

namespace greenhouse_rail_nav {

/// Settings of the rail fitting (paper Algorithm 1). base_link is taken to lie on the floor under the
/// middle of the drive wheels, so the rails' height band is measured from the floor.
struct RailDetectorParams {
  double rail_gauge_m = 0.55;       ///< centre distance of the two pipes [m]
  double gauge_tolerance_m = 0.05;  ///< the partner rail is searched at gauge +- this [m]
  double crop_z_min_m = 0.015;      ///< rails' height band in base_link [m]
  double crop_z_max_m = 0.10;
  double crop_x_min_m = 0.0;  ///< region ahead of the robot that is searched [m]
  double crop_x_max_m = 3.0;
  double crop_y_max_m = 1.5;          ///< |y| limit [m]
  double voxel_size_m = 0.02;         ///< the cropped points are thinned to one per voxel (0: off) [m]
  double cluster_tolerance_m = 0.03;  ///< Euclidean clustering distance [m]
  int min_cluster_points = 30;        ///< smaller clusters are dropped (after thinning)
  int max_cluster_points = 200000;
  double min_line_length_m = 0.3;        ///< a rail cluster is at least this long [m]
  double min_linearity = 0.97;           ///< and at least this straight (fit linearity, the paper's r)
  double rail_trim_m = 0.03;             ///< a rail's line is refitted on its points this close to it [m]
  double height_tolerance_m = 0.01;      ///< the two rails' median heights agree within this [m]
  double min_partner_coverage = 0.7;     ///< a partner taken from loose points must fill this share of 5 cm bins
  double parallel_tolerance_rad = 0.08;  ///< the partner's direction may differ by this [rad]
  double max_abs_yaw_rad = 0.8;          ///< rails are only searched within this heading of the robot [rad]
  double max_lateral_offset_m = 0.45;    ///< the rail set's centre line must pass this close to base_link [m]
  double ransac_distance_m = 0.015;      ///< baseline: RANSAC inlier distance [m]
  int ransac_max_lines = 4;              ///< baseline: lines taken by sequential RANSAC
  int ransac_iterations = 500;           ///< baseline: RANSAC iterations per line
  /// Lower bounds of the reported standard deviations (the paper's RMS errors, Table I) [m, m, rad].
  double sigma_x_m = 0.11, sigma_y_m = 0.02, sigma_yaw_rad = 0.014;
  /// The rails' start counts as seen only when the point this far in front of it lies inside the image and
  /// the floor there is seen where it lies inside the image [m]. The start is found to within about one
  /// voxel, so this is a voxel and a centimetre.
  double start_view_margin_m = 0.03;
  /// Standard deviation of x reported when the rails' start is out of view [m].
  double unobserved_sigma_x_m = 0.5;
  /// Pipe radius [m]: the camera sees the side of a pipe that faces it, whose points lie nearer the camera
  /// than the pipe's axis. Each rail's axis is found by fitting a circle of this radius to the rail's
  /// points across the rail (lateral offset, height), before thinning and trimming, so neither changes
  /// which part of the surface counts. 0: no correction (the line through the visible points).
  double pipe_radius_m = 0.0255;
  /// The rails' start counts as in view only when the point start_view_margin_m before it projects at
  /// least this far inside the image border (projection recovered from the organised cloud) [px].
  double image_margin_px = 2.0;

  /// Empty if valid, else which key is wrong and what it must be.
  std::string validate() const;
};

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
  bool pairFromLines(const std::vector<RailLine>& lines, const std::vector<Eigen::Vector3f>& band,
                     const std::vector<Eigen::Vector2d>& band_xy, bool search_points_for_partner,
                     const Eigen::Vector3d& camera_xyz, const std::vector<Eigen::Vector3f>& raw_band,
                     RailDetection* out) const;

  /// The rail's axis from the line through its visible points (see pipe_radius_m): a circle of the pipe's
  /// radius fitted to the raw band points near the line; the mean offset of a visible half-cylinder when
  /// too few points are there.
  RailLine axisLine(const RailLine& rail, const Eigen::Vector3d& camera_xyz,
                    const std::vector<Eigen::Vector3f>& raw_band) const;

  RailDetectorParams params_;
};

}  // namespace greenhouse_rail_nav
