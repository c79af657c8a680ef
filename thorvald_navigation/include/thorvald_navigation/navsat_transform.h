#pragma once

#include <array>
#include <optional>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "thorvald_navigation/utm.h"

namespace thorvald_navigation {

/// A GNSS fix as sensor_msgs/NavSatFix carries it.
struct GeoFix {
  double lat_deg = 0.0;
  double lon_deg = 0.0;
  double alt_m = 0.0;
  Eigen::Matrix3d covariance_enu = Eigen::Matrix3d::Identity();  ///< [m^2], east-north-up
};

/// The robot's pose in the world frame (x, y, z [m], yaw [rad]); roll and pitch are not used.
struct WorldPose {
  double x = 0.0, y = 0.0, z = 0.0, yaw = 0.0;
};

/// A fix in the world frame: position [m] and its covariance [m^2] rotated into the world frame.
struct WorldFix {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
};

/// Options of navsat_transform, with robot_localization's meaning.
struct NavsatOptions {
  double magnetic_declination_rad = 0.0;  ///< added to the IMU's yaw to point it at true east-north-up
  double yaw_offset_rad = 0.0;            ///< added too: an IMU whose zero yaw is not east (pi/2 for north)
  bool zero_altitude = false;             ///< world z of every fix is 0
};

/// The largest horizontal 1-sigma a fix may have to set the datum [m], by default: an RTK fixed solution's (about
/// 0.01 m) passes; a float one (0.3 m) and a single one (metres) do not, so the world frame is not offset by their
/// error. navsat_transform's `datum_max_sigma_m` and RoverFusion's datum both default to it.
constexpr double kDatumMaxSigmaM = 0.05;

/// A fix's horizontal 1-sigma [m]: the larger of east's and north's (infinity when a variance is not finite or
/// negative: an unknown covariance never sets the datum).
double horizontalSigma(const GeoFix& fix);

/// Whether a fix may set the datum (the one rule for navsat_transform and the in-process fusions): its horizontal
/// 1-sigma at most `max_sigma_m` (infinity: any fix, robot_localization's first fix). Empty, or why not.
std::string datumFixRefusal(const GeoFix& fix, double max_sigma_m);

/// The antenna's offset from base_link in the world frame [m]: its mount `antenna_in_base` (base_link -> the fix's
/// frame) turned by base_link's orientation in the world frame (roll and pitch matter: a 2.46 m mast tilted by 5 deg
/// moves the antenna 0.21 m sideways). A fix minus this offset is base_link's position.
Eigen::Vector3d antennaOffsetInWorld(const Eigen::Vector3d& antenna_in_base, const Eigen::Quaterniond& base_in_world);

/// The transform between the UTM grid and the world frame, fixed once at the datum (robot_localization's
/// navsat_transform): either from the first fix with the robot's heading (IMU yaw + declination + offset, in
/// east-north-up; turned into grid terms by the meridian convergence) and its pose in the world frame at that
/// time, or from a datum parameter [lat, lon, yaw] that puts the world origin at the datum with its x axis at
/// `yaw` (east-north-up). The UTM zone is the datum's, for every later fix. A fix is the antenna's position; with its
/// offset in the world frame (antennaOffsetInWorld) given, the datum and the fixes are base_link's.
class NavsatTransform {
 public:
  explicit NavsatTransform(const NavsatOptions& options = {}) : options_(options) {}

  /// Datum from a parameter: world origin at (lat, lon, alt), world x axis at `yaw_enu` [rad]. Empty string, or why
  /// the datum is refused (outside UTM's latitudes, not finite).
  std::string setDatum(double lat_deg, double lon_deg, double alt_m, double yaw_enu_rad);
  /// Datum from the first fix: `imu_yaw` [rad] is the IMU's yaw (declination and offset are added here), `robot`
  /// the robot's (base_link's) pose in the world frame at the fix (from odometry/filtered; zero when there is none
  /// yet), `antenna_offset` the antenna's offset from base_link in the world frame then (antennaOffsetInWorld).
  std::string setFromFix(const GeoFix& fix, double imu_yaw, const WorldPose& robot,
                         const Eigen::Vector3d& antenna_offset = Eigen::Vector3d::Zero());

  bool ready() const { return ready_; }
  /// The fix in the world frame, moved by `antenna_offset` (the antenna's offset from base_link in the world frame
  /// now: the result is base_link's; z too unless zero_altitude); nothing before the datum or for a fix outside
  /// UTM's latitudes.
  std::optional<WorldFix> toWorld(const GeoFix& fix,
                                  const Eigen::Vector3d& antenna_offset = Eigen::Vector3d::Zero()) const;
  /// Latitude and longitude of a world position (nothing before the datum).
  std::optional<LatLon> toLatLon(double x, double y) const;
  /// The UTM grid frame in the world frame: where the grid's origin is and how it is turned (x, y, z [m], yaw
  /// [rad]), for a utm -> world transform.
  std::optional<WorldPose> utmInWorld() const;
  /// The datum's UTM point (zone, hemisphere); meaningful once ready().
  const UtmPoint& datumUtm() const { return datum_utm_; }
  /// The heading in east-north-up that an IMU yaw stands for: yaw + declination + yaw_offset.
  double headingEnu(double imu_yaw) const;

 private:
  std::string set(const GeoFix& fix, double heading_enu, const WorldPose& antenna);

  NavsatOptions options_;
  bool ready_ = false;
  UtmPoint datum_utm_;
  double datum_alt_ = 0.0;
  double robot_z_ = 0.0;
  // world <- grid: p_world = rotation(yaw) * (p_grid - grid_origin) + world_origin.
  double grid_to_world_yaw_ = 0.0;
  Eigen::Vector2d grid_anchor_ = Eigen::Vector2d::Zero();
  Eigen::Vector2d world_anchor_ = Eigen::Vector2d::Zero();
};

}  // namespace thorvald_navigation
