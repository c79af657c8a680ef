#include "thorvald_navigation/navsat_transform.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include <Eigen/Geometry>

#include "thorvald_base/pose2d.h"

namespace thorvald_navigation {

namespace {

Eigen::Matrix2d rot(double yaw) { return Eigen::Rotation2Dd(yaw).toRotationMatrix(); }

}  // namespace

double horizontalSigma(const GeoFix& fix) {
  const double ve = fix.covariance_enu(0, 0), vn = fix.covariance_enu(1, 1);
  if (!std::isfinite(ve) || !std::isfinite(vn) || ve < 0.0 || vn < 0.0) return std::numeric_limits<double>::infinity();
  return std::sqrt(std::max(ve, vn));
}

std::string datumFixRefusal(const GeoFix& fix, double max_sigma_m) {
  const double sigma = horizontalSigma(fix);
  if (sigma <= max_sigma_m) return {};
  std::ostringstream why;
  why.precision(3);
  why << "the fix's horizontal sigma " << sigma << " m is above datum_max_sigma_m " << max_sigma_m << " m";
  return why.str();
}

Eigen::Vector3d antennaOffsetInWorld(const Eigen::Vector3d& antenna_in_base, const Eigen::Quaterniond& base_in_world) {
  return base_in_world.normalized() * antenna_in_base;
}

double NavsatTransform::headingEnu(double imu_yaw) const {
  return thorvald_base::normalizeAngle(imu_yaw + options_.magnetic_declination_rad + options_.yaw_offset_rad);
}

std::string NavsatTransform::setDatum(double lat_deg, double lon_deg, double alt_m, double yaw_enu_rad) {
  if (!std::isfinite(yaw_enu_rad)) return "datum yaw is not finite";
  GeoFix fix;
  fix.lat_deg = lat_deg;
  fix.lon_deg = lon_deg;
  fix.alt_m = alt_m;
  return set(fix, yaw_enu_rad, WorldPose{});
}

std::string NavsatTransform::setFromFix(const GeoFix& fix, double imu_yaw, const WorldPose& robot,
                                        const Eigen::Vector3d& antenna_offset) {
  if (!std::isfinite(imu_yaw)) return "IMU yaw is not finite";
  if (!antenna_offset.allFinite()) return "antenna offset is not finite";
  // The datum fix is the antenna's: it stands where base_link is plus the offset.
  WorldPose antenna = robot;
  antenna.x += antenna_offset.x();
  antenna.y += antenna_offset.y();
  antenna.z += antenna_offset.z();
  return set(fix, headingEnu(imu_yaw), antenna);
}

std::string NavsatTransform::set(const GeoFix& fix, double heading_enu, const WorldPose& robot) {
  if (!std::isfinite(fix.alt_m) || !std::isfinite(robot.x) || !std::isfinite(robot.y) || !std::isfinite(robot.z) ||
      !std::isfinite(robot.yaw))
    return "datum fix or robot pose is not finite";
  const std::optional<UtmPoint> utm = toUtm(fix.lat_deg, fix.lon_deg);
  if (!utm)
    return "datum (" + std::to_string(fix.lat_deg) + ", " + std::to_string(fix.lon_deg) +
           ") is outside UTM (latitude -80 ... 84 deg)";
  datum_utm_ = *utm;
  datum_alt_ = fix.alt_m;
  robot_z_ = robot.z;
  // The robot's heading in grid terms, then the rotation that takes it onto its world yaw.
  const double heading_grid = heading_enu + utmConvergence(fix.lat_deg, fix.lon_deg, utm->zone);
  grid_to_world_yaw_ = thorvald_base::normalizeAngle(robot.yaw - heading_grid);
  grid_anchor_ = {utm->easting, utm->northing};
  world_anchor_ = {robot.x, robot.y};
  ready_ = true;
  return {};
}

std::optional<WorldFix> NavsatTransform::toWorld(const GeoFix& fix, const Eigen::Vector3d& antenna_offset) const {
  if (!ready_ || !std::isfinite(fix.alt_m) || !antenna_offset.allFinite()) return std::nullopt;
  const std::optional<UtmPoint> utm = toUtm(fix.lat_deg, fix.lon_deg, datum_utm_.zone);
  if (!utm) return std::nullopt;
  // A fix across the equator from the datum keeps the datum's hemisphere's northing.
  double northing = utm->northing;
  if (utm->north != datum_utm_.north) northing += datum_utm_.north ? -1e7 : 1e7;
  WorldFix out;
  const Eigen::Vector2d p =
      rot(grid_to_world_yaw_) * (Eigen::Vector2d(utm->easting, northing) - grid_anchor_) + world_anchor_;
  out.position = {p.x() - antenna_offset.x(), p.y() - antenna_offset.y(),
                  options_.zero_altitude ? 0.0 : fix.alt_m - datum_alt_ + robot_z_ - antenna_offset.z()};
  // East-north-up covariance turned by the grid's convergence and the grid-to-world yaw (about z).
  const double yaw = grid_to_world_yaw_ + utmConvergence(fix.lat_deg, fix.lon_deg, datum_utm_.zone);
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  r.topLeftCorner<2, 2>() = rot(yaw);
  out.covariance = r * fix.covariance_enu * r.transpose();
  return out;
}

std::optional<LatLon> NavsatTransform::toLatLon(double x, double y) const {
  if (!ready_) return std::nullopt;
  const Eigen::Vector2d g = rot(-grid_to_world_yaw_) * (Eigen::Vector2d(x, y) - world_anchor_) + grid_anchor_;
  UtmPoint p = datum_utm_;
  p.easting = g.x();
  p.northing = g.y();
  return fromUtm(p);
}

std::optional<WorldPose> NavsatTransform::utmInWorld() const {
  if (!ready_) return std::nullopt;
  const Eigen::Vector2d origin = rot(grid_to_world_yaw_) * (-grid_anchor_) + world_anchor_;
  WorldPose w;
  w.x = origin.x();
  w.y = origin.y();
  w.z = options_.zero_altitude ? 0.0 : robot_z_ - datum_alt_;
  w.yaw = grid_to_world_yaw_;
  return w;
}

}  // namespace thorvald_navigation
