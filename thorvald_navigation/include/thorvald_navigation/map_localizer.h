#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "thorvald_navigation/distance_field.h"
#include "thorvald_map/occupancy_grid.h"
#include "thorvald_base/pose2d.h"
#include "thorvald_navigation/scan_matcher.h"

namespace thorvald_navigation {

/// Settings of the localiser; validate() names the bad one.
struct LocalizerParams {
  int max_beams = 180;                     ///< beams used per scan (evenly subsampled)
  double field_max_distance_m = 1.0;       ///< reach of the likelihood field [m]
  double odom_sigma_xy_m = 0.02;           ///< prior: odometry uncertainty per update, plus...
  double odom_sigma_per_m = 0.05;          ///< ...this fraction of the distance moved since the last update
  double odom_sigma_yaw_rad = 0.01;        ///< prior on heading per update, plus...
  double odom_sigma_yaw_per_rad = 0.05;    ///< ...this fraction of the rotation since the last update
  double uncertain_inlier_fraction = 0.6;  ///< below: the match is used but reported uncertain, for at most
                                           ///< lost_after_scans scans in a row (then lost)
  double lost_inlier_fraction = 0.35;      ///< below: the match is not used (odometry only)
  int lost_after_scans = 10;               ///< consecutive unusable scans before reporting lost
  int confirm_scans = 5;                   ///< good scans needed after a global localisation to be certain
  double max_jump_m = 0.5;                 ///< a correction larger than this is refused as a wrong match [m]
  /// While lost, every `recheck_every_scans` scans a search within `recheck_xy_m` / `recheck_yaw_rad` of the
  /// odometry prediction looks for the robot (an odometry jump, wheels slipping, the drive starved of CPU); its best
  /// pose is taken only when no other pose in the window matches nearly as well and at least
  /// `recheck_inlier_fraction` of the beams match. recheck_xy_m 0: no re-check (global_localization or initialpose
  /// only).
  double recheck_xy_m = 1.0;
  double recheck_yaw_rad = 0.35;
  int recheck_every_scans = 10;
  double recheck_inlier_fraction = 0.8;
  ScanMatcherParams matcher;
  GlobalSearchParams global;
  std::string validate() const;
};

enum class LocalizationStatus { kNoPose, kLocalized, kUncertain, kLost };
const char* statusName(LocalizationStatus s);

/// One localisation step's outcome.
struct LocalizationUpdate {
  bool used = false;           ///< the scan corrected the pose
  thorvald_base::Pose2D pose;  ///< base_link in the map frame
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
  double inlier_fraction = 0.0;
  LocalizationStatus status = LocalizationStatus::kNoPose;
  std::string message;  ///< why a scan was not used, or what a global search found
};

/// Localisation in a stored map from odometry and lidar: each scan is matched to the map's likelihood field,
/// starting from the odometry prediction and held to it by a prior whose width grows with the motion since the
/// last update (a scan matcher with an odometry prior instead of a particle filter). Tracks the map -> odom
/// correction, reports lost or uncertain when matches degrade, and can search the whole free map on request.
class MapLocalizer {
 public:
  explicit MapLocalizer(const LocalizerParams& params) : params_(params) {}

  /// Sets the map; an empty string on success, else what is wrong with it. `surface` (optional, the mapper's
  /// per-cell mean beam ends): scans are matched to the walls' sub-cell surface instead of the cell centres.
  std::string setMap(const thorvald_map::OccupancyGrid& map, const thorvald_map::WallSurface* surface = nullptr);
  bool hasMap() const { return !field_.empty(); }
  /// Sets the pose of base_link in the map at the moment odometry read `odom`.
  void setPose(const thorvald_base::Pose2D& map_pose, const thorvald_base::Pose2D& odom);
  /// The next scan runs a global search over the free map instead of tracking.
  void requestGlobalLocalization() {
    global_requested_ = true;
    window_xy_m_ = 0.0;
  }
  /// The next scan searches within `xy_m` [m] and `yaw_rad` [rad] of `center` (a rough pose from a user).
  void requestWindowedSearch(const thorvald_base::Pose2D& center, double xy_m, double yaw_rad) {
    global_requested_ = true;
    window_center_ = center;
    window_xy_m_ = xy_m;
    window_yaw_rad_ = yaw_rad;
  }
  /// One scan: `odom` is base_link in the odometry frame at the scan's time, `points_base` its hits in base_link.
  /// A scan whose match would move the pose by more than max_jump although it fits the map well means the pose is
  /// known to be wrong: the status turns lost at once (not after lost_after_scans) and the re-check starts.
  LocalizationUpdate update(const thorvald_base::Pose2D& odom, const std::vector<Eigen::Vector2d>& points_base);

  /// Pose of the odometry frame in the map frame (what map -> odom on tf carries).
  thorvald_base::Pose2D mapToOdom() const { return map_to_odom_; }
  LocalizationStatus status() const { return status_; }
  bool hasPose() const { return status_ != LocalizationStatus::kNoPose; }

 private:
  /// The requested global (or windowed) search, adopting its best pose when it finds one.
  void globalUpdate(const thorvald_base::Pose2D& odom, const std::vector<Eigen::Vector2d>& points_base,
                    LocalizationUpdate* u);
  /// Scan-matcher parameters whose odometry prior widens with the motion since the last scan (more when lost).
  ScanMatcherParams trackingParams(const thorvald_base::Pose2D& odom) const;
  /// Counts a poor, jumping or weak match, updates the status and fills u with the prediction; true when rejected.
  bool rejectMatch(const MatchResult& m, const thorvald_base::Pose2D& predicted, LocalizationUpdate* u);
  /// Takes a good match as the new map-to-odometry transform and updates the status (confirmation after lost).
  void acceptMatch(const MatchResult& m, const thorvald_base::Pose2D& odom, LocalizationUpdate* u);
  /// Takes a search's best pose (status uncertain until confirm_scans good scans agree), fills `u`.
  void adopt(const GlobalResult& g, const thorvald_base::Pose2D& odom, const std::string& what, LocalizationUpdate* u);
  /// The lost robot's windowed search around the odometry prediction; true when it relocalised.
  bool recheck(const thorvald_base::Pose2D& odom, const std::vector<Eigen::Vector2d>& points_base,
               LocalizationUpdate* u);

  LocalizerParams params_;
  thorvald_map::OccupancyGrid map_;
  DistanceField field_;
  thorvald_base::Pose2D map_to_odom_;
  thorvald_base::Pose2D last_odom_;
  bool have_last_odom_ = false;
  bool global_requested_ = false;
  thorvald_base::Pose2D window_center_;
  double window_xy_m_ = 0.0, window_yaw_rad_ = thorvald_base::kPi;
  int bad_scans_ = 0;
  int weak_scans_ = 0;  // consecutive matches below uncertain_inlier_fraction
  int confirm_left_ = 0;
  int scans_to_recheck_ = 0;
  LocalizationStatus status_ = LocalizationStatus::kNoPose;
};

}  // namespace thorvald_navigation
