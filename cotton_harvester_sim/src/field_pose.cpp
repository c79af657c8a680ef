#include "cotton_harvester_sim/field_pose.h"

#include <cmath>
#include <cstdio>

namespace cotton_harvester {
namespace sim {

std::optional<std::string> DriveGate::update(const thorvald_navigation::FusionHealth& health, double t) {
  if (!health.localization_ok) {
    ok_since_.reset();
    const std::string why = health.summary();
    if (!stopped_) {
      stopped_ = true;
      stopped_at_ = t;
      ++stops_;
      reason_ = why;
      return "stopped: " + why;
    }
    reason_ = why;
    return std::nullopt;
  }
  if (!stopped_) return std::nullopt;
  if (!ok_since_) ok_since_ = t;
  if (t - *ok_since_ < resume_after_s_) return std::nullopt;
  stopped_ = false;
  reason_.clear();
  ok_since_.reset();
  stopped_total_s_ += t - stopped_at_;
  char line[96];
  std::snprintf(line, sizeof line, "resumed: localization ok again after %.1f s stopped", t - stopped_at_);
  return std::string(line);
}

FieldPose::FieldPose(const RoverSim& sim, unsigned seed, const RoverFusionParams& fusion,
                     std::optional<thorvald_sim::Realism> sensors) {
  RoverSensorParams sp;
  sp.realism = sensors;
  sp.seed = seed;
  sp.gnss.seed = seed;
  sensors_ = std::make_unique<RoverSensors>(sim, sp);
  RoverFusionParams fp = fusion;
  fp.axle_to_joint_m = sim.params().geometry.axle_to_joint_m;
  fp.metres_per_pulse = sim.params().drive.metres_per_pulse;
  fusion_ = std::make_unique<RoverFusion>(SensorSet::kOdometryTwoImusGnss, fp,
                                          std::vector<Eigen::Vector3d>{sensors_->antennaInBase(0)});
  const thorvald_sim::GnssModelParams& g = sensors_->gnss(0).params();
  datum_ = {g.datum_latitude_deg, g.datum_longitude_deg, g.datum_altitude_m};
}

std::optional<Eigen::Vector2d> FieldPose::enuOf(double x, double y) const {
  const std::optional<thorvald_navigation::LatLon> ll = fusion_->toLatLon(x, y);
  if (!ll) return std::nullopt;
  return datum_.toEnu(ll->lat_deg, ll->lon_deg, datum_.altitude_m).head<2>();
}

void FieldPose::afterStep() {
  const RoverSensorFrame f = sensors_->poll();
  if (f.wheels) fusion_->onWheels(*f.wheels);
  for (const ImuReading& imu : f.imu) fusion_->onImu(imu);
  for (const GnssReading& g : f.gnss) fusion_->onGnss(g);
  if (to_enu_) return;
  // Once the datum is set: the fusion's frame in the field's, from two points 100 m apart (UTM's scale and grid
  // convergence included).
  const std::optional<Eigen::Vector2d> a = enuOf(0.0, 0.0), b = enuOf(100.0, 0.0);
  if (!a || !b) return;
  const Eigen::Vector2d d = *b - *a;
  to_enu_ = Similarity{std::atan2(d.y(), d.x()), d.norm() / 100.0, *a};
}

control::Pose2 FieldPose::estimate(double t) {
  const RoverPose2d p = fusion_->estimate(t);
  if (!to_enu_) return {p.x, p.y, p.yaw};
  const Similarity& s = *to_enu_;
  const Eigen::Vector2d q = s.offset + s.scale * (Eigen::Rotation2Dd(s.angle) * Eigen::Vector2d(p.x, p.y));
  return {q.x(), q.y(), control::wrapAngle(p.yaw + s.angle)};
}

}  // namespace sim
}  // namespace cotton_harvester
