#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "thorvald_navigation/distance_field.h"
#include "thorvald_base/pose2d.h"

namespace thorvald_navigation {

/// Settings of the scan matcher; validate() names the bad one.
struct ScanMatcherParams {
  double sigma_hit_m = 0.05;         ///< expected beam end-point error; scale of the robust (Cauchy) weight [m]
  double coarse_sigma_m = 0.2;       ///< a first pass with this wider scale widens convergence; 0: none [m]
  double inlier_m = 0.10;            ///< a beam end within this of a wall counts as matched [m]
  int max_iterations = 25;           ///< Gauss-Newton iterations per match
  double prior_sigma_xy_m = 0.0;     ///< pull towards the prior pose; 0: none [m]
  double prior_sigma_yaw_rad = 0.0;  ///< 0: none [rad]
  std::string validate() const;
};

/// The result of aligning one scan to a map.
struct MatchResult {
  thorvald_base::Pose2D pose;                                ///< base_link in the map frame
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();  ///< of (x, y, yaw) [m^2, rad^2]
  double inlier_fraction = 0.0;                              ///< beams ending within inlier_m of a wall [0..1]
  double rms_m = 0.0;  ///< rms distance of the inlier beams to the nearest wall [m]
  int points = 0;      ///< beams used
  int iterations = 0;
};

/// Aligns 2D points (beam end points in base_link [m]) to a distance field by Gauss-Newton with a Cauchy
/// robust weight, optionally with a Gaussian prior on the pose (the odometry prediction). Converges from within
/// about the field's max distance and a few tenths of a radian; use globalSearch() from farther.
MatchResult matchScan(const DistanceField& field, const std::vector<Eigen::Vector2d>& points_base,
                      const thorvald_base::Pose2D& initial, const ScanMatcherParams& params);

/// Settings of the exhaustive search used for global localisation.
struct GlobalSearchParams {
  double step_xy_m = 0.2;        ///< candidate position spacing [m]
  double step_yaw_rad = 0.0873;  ///< candidate heading spacing (5 deg) [rad]
  int max_points = 60;           ///< beams scored per candidate (evenly subsampled)
  int refine_best = 12;          ///< best candidates refined with matchScan
  double min_clearance_m = 0.2;  ///< candidates closer than this to a wall are skipped [m]
  /// Search only around `center` when window_xy_m > 0: within window_xy_m [m] and window_yaw_rad [rad].
  double window_xy_m = 0.0;
  double window_yaw_rad = thorvald_base::kPi;
  thorvald_base::Pose2D center;
  std::string validate() const;
};

/// A global pose hypothesis: the best refined match, the runner-up that is not the same place, and whether the
/// two are too close in quality to tell apart.
struct GlobalResult {
  bool found = false;
  MatchResult best;
  MatchResult runner_up;  ///< inlier_fraction 0 when there is none
  bool ambiguous = false;
  int candidates = 0;  ///< poses scored
};

/// Scores every free pose of `free_space` (cells 0..19) on a grid (or within the window around a centre) and
/// refines the best ones. Cost grows with searched area x headings x max_points.
GlobalResult globalSearch(const DistanceField& field, const thorvald_map::OccupancyGrid& free_space,
                          const std::vector<Eigen::Vector2d>& points_base, const GlobalSearchParams& gparams,
                          const ScanMatcherParams& params);

/// Evenly picks at most `max_points` of `points` (keeps the order).
std::vector<Eigen::Vector2d> subsample(const std::vector<Eigen::Vector2d>& points, int max_points);

}  // namespace thorvald_navigation
