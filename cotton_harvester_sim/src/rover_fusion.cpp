#include "cotton_harvester_sim/rover_fusion.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cotton_harvester {
namespace sim {

namespace tn = thorvald_navigation;

namespace {

constexpr const char* kOdom = "odom0 (odometry/wheel)";
constexpr const char* kImu[2] = {"imu0 (imu0/data)", "imu1 (imu1/data)"};
constexpr const char* kGnss[2] = {"odom1 (odometry/gps)", "odom2 (odometry/gps2)"};

bool usesImu(SensorSet set, int index) {
  if (set == SensorSet::kOdometry) return false;
  return index == 0 || set != SensorSet::kOdometryImu;
}

/// The fix with the receiver's own sigma, its variance scaled for a float or single solution's correlated error.
tn::GeoFix geoFix(const thorvald_sim::GnssSolution& s, const RoverFusionParams& p) {
  tn::GeoFix f;
  f.lat_deg = s.latitude_deg;
  f.lon_deg = s.longitude_deg;
  f.alt_m = s.altitude_m;
  double tau = 0.0;
  if (s.state == thorvald_sim::GnssFixState::kFloat) tau = p.float_correlation_s;
  if (s.state == thorvald_sim::GnssFixState::kSingle) tau = p.single_correlation_s;
  const double scale = std::max(1.0, 2.0 * tau / p.gnss_period_s);
  f.covariance_enu = scale * s.sigma_m.cwiseAbs2().asDiagonal();
  return f;
}

}  // namespace

const char* sensorSetName(SensorSet set) {
  switch (set) {
    case SensorSet::kOdometry:
      return "Odometry (dead reckoning)";
    case SensorSet::kOdometryImu:
      return "Odometry + one IMU";
    case SensorSet::kOdometryTwoImus:
      return "Odometry + two IMUs";
    case SensorSet::kOdometryTwoImusGnss:
      return "Odometry + two IMUs + one GNSS";
    case SensorSet::kOdometryTwoImusTwoGnss:
      return "Odometry + two IMUs + two GNSSs";
  }
  return "?";
}

const char* sensorSetKey(SensorSet set) {
  static constexpr const char* kKeys[] = {"odom", "odom_imu", "odom_2imu", "odom_2imu_gnss", "odom_2imu_2gnss"};
  return kKeys[static_cast<int>(set)];
}

int gnssReceiversOf(SensorSet set) {
  return set == SensorSet::kOdometryTwoImusGnss ? 1 : set == SensorSet::kOdometryTwoImusTwoGnss ? 2 : 0;
}

RoverFusion::RoverFusion(SensorSet set, const RoverFusionParams& params,
                         const std::vector<Eigen::Vector3d>& antennas_in_base)
    : set_(set), p_(params), antennas_(antennas_in_base), wheels_(params.axle_to_joint_m, params.metres_per_pulse) {
  ekf_.setTwoDMode(true);
  tn::Cov15 q = tn::FusionEkf::defaultProcessNoise();
  q(tn::kFx, tn::kFx) = q(tn::kFy, tn::kFy) = p_.position_process_noise;
  ekf_.setProcessNoise(q);
  monitor_.addInput(kOdom, p_.input_timeout_s, true);
  for (int i = 0; i < 2; ++i)
    if (usesImu(set, i)) monitor_.addInput(kImu[i], p_.input_timeout_s, true);
  for (int r = 0; r < gnssReceiversOf(set) && r < static_cast<int>(antennas_.size()); ++r) {
    monitor_.addInput(kGnss[r], p_.gnss_timeout_s, true);
    navsat_.emplace_back();
  }
}

void RoverFusion::fuse(const std::string& input, double t, const std::vector<tn::Measurement>& z) {
  monitor_.received(input, t);
  if (!ekf_.initialized()) {
    ekf_.reset(tn::State15::Zero(), t);
    monitor_.setStart(t);
  }
  if (t > ekf_.time()) ekf_.predict(t);
  for (const tn::Measurement& m : z) {
    const tn::UpdateResult r = ekf_.update(m.entries, m.gate_sigma);
    if (r.fused())
      monitor_.fused(input);
    else
      monitor_.refused(input, m.part + ": " + r.error);
  }
}

void RoverFusion::onWheels(const WheelReading& w) {
  if (!wheels_.add(w)) return;
  const control::ArticulatedOdometry& o = wheels_.odometry();
  fuse(kOdom, w.time_s,
       {{{{tn::kFvx, o.speed(), p_.speed_variance},
          {tn::kFvy, 0.0, p_.vy_variance},
          {tn::kFvyaw, o.yawRate(), p_.yaw_rate_variance}},
         std::numeric_limits<double>::infinity(),
         "twist"}});
}

void RoverFusion::onImu(const ImuReading& imu) {
  const double yaw = tn::rollPitchYaw(imu.orientation).z();
  if (imu.index == 0) imu0_yaw_ = yaw;
  if (!usesImu(set_, imu.index)) return;
  // Both IMUs sit level on the front half, x forward: their frames are base_link's (identity mount).
  std::vector<tn::Measurement> z;
  if (imu.index == 0) z.push_back({{{tn::kFyaw, yaw, p_.imu_yaw_variance}}, 10.0 * p_.gnss_gate_sigma, "orientation"});
  z.push_back({{{tn::kFvyaw, imu.gyro_radps.z(), p_.imu_rate_variance}},
               std::numeric_limits<double>::infinity(),
               "angular velocity"});
  fuse(kImu[imu.index], imu.time_s, z);
}

void RoverFusion::onGnss(const GnssReading& g) {
  const int r = g.receiver;
  if (r >= static_cast<int>(navsat_.size())) return;
  // No fix: nothing to fuse; the input's timeout (gnss_timeout_s) says when the rover has to stop.
  if (g.solution.state < p_.min_fix_state) return;
  const tn::GeoFix fix = geoFix(g.solution, p_);
  const double t = g.solution.time_s;
  if (!ekf_.initialized()) return;  // the datum needs the filter's pose
  if (t > ekf_.time()) ekf_.predict(t);
  const tn::State15& x = ekf_.state();
  const double yaw = x(tn::kFyaw);
  // The antenna's offset from base_link with the filter's heading (the filter is planar: no roll or pitch).
  const Eigen::Vector3d lever =
      tn::antennaOffsetInWorld(antennas_[r], Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ())));
  if (!navsat_[r].ready()) {
    // Datum at the first fix good enough for it (navsat_transform's rule: an RTK fixed epoch).
    if (!tn::datumFixRefusal(fix, p_.datum_max_sigma_m).empty() || !imu0_yaw_) return;
    if (!navsat_[r].setFromFix(fix, *imu0_yaw_, tn::WorldPose{x(tn::kFx), x(tn::kFy), 0.0, yaw}, lever).empty()) return;
  }
  const std::optional<tn::WorldFix> w = navsat_[r].toWorld(fix, lever);
  if (!w) return;
  const Eigen::Vector2d base = w->position.head<2>();
  monitor_.received(kGnss[r], t);
  const tn::UpdateResult u = ekf_.update(
      {{tn::kFx, base.x(), w->covariance(0, 0)}, {tn::kFy, base.y(), w->covariance(1, 1)}}, p_.gnss_gate_sigma);
  if (u.fused()) {
    ++gnss_fused_;
    monitor_.fused(kGnss[r]);
  } else {
    ++gnss_refused_;
    monitor_.refused(kGnss[r], "pose: " + u.error);
  }
}

RoverPose2d RoverFusion::estimate(double t) {
  if (ekf_.initialized() && t > ekf_.time()) ekf_.predict(t);
  const tn::State15& x = ekf_.state();
  return {x(tn::kFx), x(tn::kFy), x(tn::kFyaw)};
}

std::optional<tn::LatLon> RoverFusion::toLatLon(double x, double y) const {
  if (navsat_.empty()) return std::nullopt;
  return navsat_[0].toLatLon(x, y);
}

Eigen::Vector2d RoverFusion::positionSigma() const {
  const tn::Cov15& p = ekf_.covariance();
  return {std::sqrt(std::max(0.0, p(tn::kFx, tn::kFx))), std::sqrt(std::max(0.0, p(tn::kFy, tn::kFy)))};
}

}  // namespace sim
}  // namespace cotton_harvester
