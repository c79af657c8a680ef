#include "cotton_harvester_sim/rover_sensors.h"

#include <cmath>
#include <stdexcept>

#include <mujoco/mujoco.h>
#include <thorvald_sim/nmea_sentences.h>

#include "cotton_harvester_sim/rover_scene.h"

namespace cotton_harvester {
namespace sim {

namespace {

constexpr double kGravity = 9.80665;

bool positiveFinite(double v) { return std::isfinite(v) && v > 0.0; }

int idOf(const mjModel* m, mjtObj type, const char* name) {
  const int i = mj_name2id(m, type, name);
  if (i < 0) throw std::invalid_argument(std::string("rover sensors: the scene has no ") + name);
  return i;
}

}  // namespace

std::string RoverSensorParams::check() const {
  if (!positiveFinite(imu_rate_hz) || imu_rate_hz > 1000.0) return "imu_rate_hz: expected within (0, 1000]";
  if (!positiveFinite(wheel_rate_hz) || wheel_rate_hz > 1000.0) return "wheel_rate_hz: expected within (0, 1000]";
  if (!(pot_noise_counts >= 0.0) || !std::isfinite(pot_noise_counts)) return "pot_noise_counts: expected >= 0";
  if (const char* bad = pot.check(); bad && *bad) return bad;
  const double lengths[] = {mounts.imu0_from_front_m, mounts.imu0_height_m,     mounts.imu1_from_front_m,
                            mounts.imu1_height_m,     mounts.gnss_from_front_m, mounts.gnss_height_m};
  for (double v : lengths)
    if (!(v >= 0.0) || !std::isfinite(v)) return "mounts: expected finite lengths >= 0";
  if (!std::isfinite(mounts.gnss2_left_m)) return "mounts.gnss2_left_m: expected finite";
  const auto problems = gnss.validate();
  return problems.empty() ? "" : "gnss: " + problems.front();
}

thorvald_sim::GnssModelParams roverGnssParams(thorvald_sim::Realism realism,
                                              const thorvald_sim::GnssModelParams& base) {
  thorvald_sim::GnssModelParams p = base;
  if (realism == thorvald_sim::Realism::kIdeal) {
    p.fixed = {0.001, 0.001, 2.0, 18, 0.6};  // every state as good: an ideal receiver is never off
    p.floating = {0.001, 0.001, 2.0, 14, 0.9};
    p.single = {0.001, 0.001, 2.0, 10, 1.3};
    p.single_acquire_s = p.float_acquire_s = p.fixed_acquire_s = 0.0;
  }
  return p;
}

RoverSensors::RoverSensors(const RoverSim& sim, const RoverSensorParams& params)
    : sim_(sim),
      params_(params),
      datasheet_(params.realism.value_or(sim.params().realism) == thorvald_sim::Realism::kDatasheet),
      rng_(params.seed),
      pot_(params.pot) {
  if (auto bad = params_.check(); !bad.empty()) throw std::invalid_argument("rover sensors: " + bad);
  const mjModel* m = sim_.model();
  front_body_ = idOf(m, mjOBJ_BODY, "rover_front");
  for (int w = 0; w < 2; ++w) {
    wheel_qpos_[w] = m->jnt_qposadr[idOf(m, mjOBJ_JOINT, kRoverWheelNames[w])];
    wheel_start_[w] = sim_.data()->qpos[wheel_qpos_[w]];
  }
  const RoverGeometry& g = sim_.params().geometry;
  base_in_front_x_ = g.axle_to_joint_m;
  // The front body's frame: at the articulation joint, at the wheels' centre height.
  auto mount = [&g](double from_front, double height, double left) {
    return Eigen::Vector3d(g.front_length_m - from_front, left, height - g.wheel_radius_m);
  };
  const RoverSensorMounts& mt = params_.mounts;
  imus_[0].in_front = mount(mt.imu0_from_front_m, mt.imu0_height_m, 0.0);
  imus_[1].in_front = mount(mt.imu1_from_front_m, mt.imu1_height_m, 0.0);
  antennas_in_front_.push_back(mount(mt.gnss_from_front_m, mt.gnss_height_m, 0.0));
  if (params_.second_gnss) antennas_in_front_.push_back(mount(mt.gnss_from_front_m, mt.gnss_height_m, mt.gnss2_left_m));
  const thorvald_sim::ImuModel model = thorvald_sim::phidget1044ImuModel();
  const Eigen::Quaterniond start(frontRotation());
  for (ImuState& imu : imus_) {
    if (datasheet_) imu.errors = std::make_unique<thorvald_sim::ImuErrors>(model, rng_);
    imu.orientation = start;
  }
  for (size_t r = 0; r < antennas_in_front_.size(); ++r) {
    thorvald_sim::GnssModelParams gp = roverGnssParams(params_.realism.value_or(sim_.params().realism), params_.gnss);
    gp.seed = params_.gnss.seed + 7919u * r;
    gnss_.push_back(std::make_unique<thorvald_sim::GnssModel>(gp));
  }
  next_imu_s_ = next_wheels_s_ = sim_.time();
}

Eigen::Matrix3d RoverSensors::frontRotation() const {
  return Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(sim_.data()->xmat + 9 * front_body_);
}

Eigen::Vector3d RoverSensors::frontPointWorld(const Eigen::Vector3d& in_front) const {
  const Eigen::Map<const Eigen::Vector3d> p(sim_.data()->xpos + 3 * front_body_);
  return p + frontRotation() * in_front;
}

Eigen::Vector3d RoverSensors::frontPointVelocity(const Eigen::Vector3d& in_front, Eigen::Vector3d* omega_world) const {
  mjtNum v[6];
  mj_objectVelocity(sim_.model(), sim_.data(), mjOBJ_BODY, front_body_, v, 0);  // at the body's origin, world axes
  const Eigen::Vector3d omega(v[0], v[1], v[2]), linear(v[3], v[4], v[5]);
  if (omega_world) *omega_world = omega;
  return linear + omega.cross(frontRotation() * in_front);
}

Eigen::Vector3d RoverSensors::imuInBase(int index) const {
  return imus_.at(index).in_front - Eigen::Vector3d(base_in_front_x_, 0.0, 0.0);
}

Eigen::Vector3d RoverSensors::antennaInBase(int receiver) const {
  return antennas_in_front_.at(receiver) - Eigen::Vector3d(base_in_front_x_, 0.0, 0.0);
}

Eigen::Vector3d RoverSensors::worldPointOfBase(const Eigen::Vector3d& in_base) const {
  return frontPointWorld(in_base + Eigen::Vector3d(base_in_front_x_, 0.0, 0.0));
}

RoverPose2d RoverSensors::truthPose() const {
  const Eigen::Vector3d p = worldPointOfBase(Eigen::Vector3d::Zero());
  const Eigen::Matrix3d r = frontRotation();
  return {p.x(), p.y(), std::atan2(r(1, 0), r(0, 0))};
}

ImuReading RoverSensors::readImu(int index, double t) {
  ImuState& s = imus_[index];
  Eigen::Vector3d omega;
  const Eigen::Vector3d velocity = frontPointVelocity(s.in_front, &omega);
  Eigen::Vector3d accel_world = Eigen::Vector3d::Zero();
  const double dt = t - s.last_t;
  const bool started = s.last_velocity.has_value();
  if (started && dt > 0.0) accel_world = (velocity - *s.last_velocity) / dt;
  s.last_velocity = velocity;
  const Eigen::Matrix3d r = frontRotation();
  ImuReading out;
  out.index = index;
  out.time_s = t;
  out.gyro_radps = r.transpose() * omega;
  out.accel_mps2 = r.transpose() * (accel_world + Eigen::Vector3d(0.0, 0.0, kGravity));
  if (s.errors) s.errors->apply(t, &out.gyro_radps, &out.accel_mps2, rng_);
  // The driver's orientation: the measured rate integrated in the sensor's frame.
  if (started && dt > 0.0) {
    const Eigen::Vector3d turn = out.gyro_radps * dt;
    const double angle = turn.norm();
    if (angle > 0.0) s.orientation = (s.orientation * Eigen::Quaterniond(Eigen::AngleAxisd(angle, turn / angle)));
    s.orientation.normalize();
  }
  s.last_t = t;
  out.orientation = s.orientation;
  return out;
}

WheelReading RoverSensors::readWheels(double t) {
  const double radius = sim_.params().geometry.wheel_radius_m, per_pulse = sim_.params().drive.metres_per_pulse;
  WheelReading w;
  w.time_s = t;
  std::int32_t pulses[2];
  for (int i = 0; i < 2; ++i) {
    const double travel = (sim_.data()->qpos[wheel_qpos_[i]] - wheel_start_[i]) * radius;
    pulses[i] = static_cast<std::int32_t>(std::trunc(travel / per_pulse));
  }
  w.left_pulses = pulses[0];
  w.right_pulses = pulses[1];
  double counts = pot_.potFromAngle(sim_.potentiometerDeg());
  if (datasheet_ && params_.pot_noise_counts > 0.0) {
    std::uniform_real_distribution<double> noise(-params_.pot_noise_counts, params_.pot_noise_counts);
    counts = std::round(counts + noise(rng_));
  }
  w.pot_counts = counts;
  w.articulation_deg = pot_.angleFromPot(counts);
  return w;
}

RoverSensorFrame RoverSensors::poll() {
  const double t = sim_.time();
  RoverSensorFrame f;
  if (t + 1e-9 >= next_imu_s_) {
    for (int i = 0; i < 2; ++i) f.imu.push_back(readImu(i, t));
    while (next_imu_s_ <= t + 1e-9) next_imu_s_ += 1.0 / params_.imu_rate_hz;
  }
  if (t + 1e-9 >= next_wheels_s_) {
    f.wheels = readWheels(t);
    while (next_wheels_s_ <= t + 1e-9) next_wheels_s_ += 1.0 / params_.wheel_rate_hz;
  }
  for (size_t r = 0; r < gnss_.size(); ++r) {
    // The local east-north-up frame is the world frame; its origin is the GNSS datum.
    const auto solution = gnss_[r]->update(t, frontPointWorld(antennas_in_front_[r]));
    if (!solution) continue;
    GnssReading g;
    g.receiver = static_cast<int>(r);
    g.solution = *solution;
    g.sentences = thorvald_sim::epochSentences(*solution);
    f.gnss.push_back(std::move(g));
  }
  return f;
}

bool EncoderOdometry::add(const WheelReading& w) {
  const bool step = last_ && w.time_s > last_->time_s;
  if (step) {
    const double pulses = 0.5 * ((w.left_pulses - last_->left_pulses) + (w.right_pulses - last_->right_pulses));
    odometry_.update(pulses * metres_per_pulse_, w.articulation_deg, w.time_s - last_->time_s);
  }
  last_ = w;
  return step;
}

}  // namespace sim
}  // namespace cotton_harvester
