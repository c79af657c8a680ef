#include "thorvald_sim/sensors.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace thorvald_sim {

Intrinsics intrinsics(int width, int height, double hfov_rad) {
  const double f = 0.5 * width / std::tan(0.5 * hfov_rad);
  return {f, f, 0.5 * (width - 1), 0.5 * (height - 1)};
}

namespace {

/// Beam sectors: a geom's bounding sphere meets the scan plane in a circle that only the beams within its angular
/// half-width can hit. `sector[i]` gets the geoms beam i can meet, `everywhere` the planes and the geoms around the
/// sensor. A sensor that moves during the scan (by at most margin_m and margin_rad from `pose`) widens each sphere
/// and each sector by those margins.
void beamSectors(const RayCaster& caster, const SensorPose& pose, const LidarSpec& s, double margin_m,
                 double margin_rad, std::vector<std::vector<int>>* sector, std::vector<int>* everywhere) {
  const double inc = s.samples > 1 ? (s.angle_max_rad - s.angle_min_rad) / (s.samples - 1) : 0.0;
  const mjModel* m = caster.model();
  const mjData* d = caster.data();
  sector->assign(s.samples, {});
  for (int g : caster.prepared()) {
    if (m->geom_type[g] == mjGEOM_PLANE || inc <= 0.0) {
      everywhere->push_back(g);
      continue;
    }
    const Eigen::Vector3d c(d->geom_xpos[3 * g], d->geom_xpos[3 * g + 1], d->geom_xpos[3 * g + 2]);
    const Eigen::Vector3d p = pose.rotation.transpose() * (c - pose.origin);
    const double rb = m->geom_rbound[g] * (1.0 + 1e-9) + 1e-9 + margin_m;
    if (std::fabs(p.z()) > rb) continue;  // the scan plane passes above or below it
    const double r_plane = std::sqrt(rb * rb - p.z() * p.z()), dist = std::hypot(p.x(), p.y());
    if (dist <= r_plane) {  // the sensor is inside: every direction
      everywhere->push_back(g);
      continue;
    }
    const double centre = std::atan2(p.y(), p.x()), half = std::asin(r_plane / dist) + margin_rad;
    for (double wrap : {-2 * M_PI, 0.0, 2 * M_PI}) {
      const double lo = centre + wrap - half, hi = centre + wrap + half;
      const int i0 = std::max(0, static_cast<int>(std::ceil((lo - s.angle_min_rad) / inc - 1e-9)));
      const int i1 = std::min(s.samples - 1, static_cast<int>(std::floor((hi - s.angle_min_rad) / inc + 1e-9)));
      for (int i = i0; i <= i1; ++i) (*sector)[i].push_back(g);
    }
  }
}

/// The datasheet scan: each beam's true range and incidence from the pose at its time, then the LidarModel.
std::vector<float> datasheetScan(RayCaster& caster, const SensorPose& start, const SensorPose& end, const LidarSpec& s,
                                 std::mt19937& rng) {
  const double turn = std::min(1.0, (s.angle_max_rad - s.angle_min_rad) / (2 * M_PI));
  const SensorPose mid = interpolatePose(start, end, 0.5 * turn);
  const double margin_m = 0.5 * turn * (end.origin - start.origin).norm() + 1e-9;
  const double margin_rad = 0.5 * turn * Eigen::AngleAxisd(start.rotation.transpose() * end.rotation).angle() + 1e-9;
  caster.prepare(mid.origin, s.range_max_m + margin_m, mid.rotation.col(0), M_PI);
  std::vector<std::vector<int>> sector;
  std::vector<int> everywhere, beam;
  beamSectors(caster, mid, s, margin_m, margin_rad, &sector, &everywhere);
  const double inc = s.samples > 1 ? (s.angle_max_rad - s.angle_min_rad) / (s.samples - 1) : 0.0;
  std::vector<LidarBeam> beams(s.samples);
  for (int i = 0; i < s.samples; ++i) {
    const double a = s.angle_min_rad + i * inc;
    const SensorPose p = interpolatePose(start, end, (a - s.angle_min_rad) / (2 * M_PI));
    const Eigen::Vector3d dir = p.rotation * Eigen::Vector3d(std::cos(a), std::sin(a), 0.0);
    beam.assign(everywhere.begin(), everywhere.end());
    beam.insert(beam.end(), sector[i].begin(), sector[i].end());
    int g = -1;
    const double r = caster.castAmong(p.origin, dir, beam.data(), beam.data() + beam.size(), &g);
    if (r < 0.0) continue;
    const Eigen::Vector3d n = caster.normal(g, p.origin + r * dir, dir);
    beams[i] = {r, std::acos(std::clamp(-n.dot(dir), -1.0, 1.0))};
  }
  return applyLidarModel(beams, s.range_min_m, s.range_max_m, s.model, rng);
}

}  // namespace

SensorPose interpolatePose(const SensorPose& a, const SensorPose& b, double f) {
  SensorPose p;
  p.origin = a.origin + f * (b.origin - a.origin);
  p.rotation = Eigen::Quaterniond(a.rotation).slerp(f, Eigen::Quaterniond(b.rotation)).toRotationMatrix();
  return p;
}

SensorPose advancePose(const SensorPose& p, const Eigen::Vector3d& v_mps, const Eigen::Vector3d& w_radps, double dt_s) {
  SensorPose q;
  q.origin = p.origin + dt_s * v_mps;
  const double angle = w_radps.norm() * dt_s;
  q.rotation = angle > 0.0 ? Eigen::Matrix3d(Eigen::AngleAxisd(angle, w_radps.normalized()) * p.rotation) : p.rotation;
  return q;
}

SensorPose sweepEnd(const mjModel* model, const mjData* data, int body, const SensorPose& pose, double dt_s) {
  mjtNum vel[6];
  mj_objectVelocity(model, data, mjOBJ_BODY, body, vel, 0);  // [angular; linear] at the body's centre of mass, world
  const Eigen::Vector3d w(vel[0], vel[1], vel[2]), v_com(vel[3], vel[4], vel[5]);
  const Eigen::Vector3d com(data->xipos[3 * body], data->xipos[3 * body + 1], data->xipos[3 * body + 2]);
  return advancePose(pose, v_com + w.cross(pose.origin - com), w, dt_s);
}

std::vector<float> simulateLidar(RayCaster& caster, const SensorPose& pose, const LidarSpec& s, std::mt19937& rng,
                                 const SensorPose* sweep_end) {
  if (s.realism == Realism::kDatasheet) return datasheetScan(caster, pose, sweep_end ? *sweep_end : pose, s, rng);
  caster.prepare(pose.origin, s.range_max_m, pose.rotation.col(0), M_PI);
  std::normal_distribution<double> noise(0.0, s.noise_m);
  std::vector<float> ranges(s.samples, std::numeric_limits<float>::infinity());
  const double inc = s.samples > 1 ? (s.angle_max_rad - s.angle_min_rad) / (s.samples - 1) : 0.0;
  // Each beam tests the planes and the few geoms of its own sector.
  std::vector<std::vector<int>> sector;
  std::vector<int> everywhere;
  beamSectors(caster, pose, s, 0.0, 0.0, &sector, &everywhere);
  std::vector<int> beam;
  for (int i = 0; i < s.samples; ++i) {
    const double a = s.angle_min_rad + i * inc;
    const Eigen::Vector3d dir = pose.rotation * Eigen::Vector3d(std::cos(a), std::sin(a), 0.0);
    beam.assign(everywhere.begin(), everywhere.end());
    beam.insert(beam.end(), sector[i].begin(), sector[i].end());
    const double r = caster.castAmong(pose.origin, dir, beam.data(), beam.data() + beam.size());
    const double n = s.noise_m > 0 ? noise(rng) : 0.0;
    if (r >= s.range_min_m && r <= s.range_max_m) ranges[i] = static_cast<float>(r + n);
  }
  return ranges;
}

double simulateUltrasonic(RayCaster& caster, const SensorPose& pose, const UltrasonicSpec& s, std::mt19937& rng) {
  const Eigen::Vector3d axis = pose.rotation.col(0);
  caster.prepare(pose.origin, s.range_max_m, axis, 0.5 * s.fov_rad);
  const bool datasheet = s.realism == Realism::kDatasheet;
  double best = std::numeric_limits<double>::infinity();
  std::vector<EchoRay> rays;
  auto probe = [&](double elevation, double azimuth) {
    const Eigen::Vector3d local(std::cos(elevation), std::sin(elevation) * std::cos(azimuth),
                                std::sin(elevation) * std::sin(azimuth));
    const Eigen::Vector3d dir = pose.rotation * local;
    int g = -1;
    const double d = caster.cast(pose.origin, dir, &g);
    if (datasheet && d >= 0.0) {
      const Eigen::Vector3d n = caster.normal(g, pose.origin + d * dir, dir);
      rays.push_back({d, std::acos(std::clamp(-n.dot(dir), -1.0, 1.0))});
    }
    if (d >= 0.0 && d < best) best = d;
  };
  probe(0.0, 0.0);
  for (int r = 1; r <= s.rings; ++r)
    for (int k = 0; k < s.rays_per_ring; ++k)
      probe(0.5 * s.fov_rad * r / s.rings, 2 * M_PI * (k + 0.5 * (r % 2)) / s.rays_per_ring);
  if (datasheet) best = nearestEcho(rays, s.model);
  if (best > s.range_max_m) return std::numeric_limits<double>::infinity();
  std::normal_distribution<double> noise(0.0, s.noise_m);
  return std::max(s.range_min_m, best + (s.noise_m > 0 ? noise(rng) : 0.0));
}

namespace {

constexpr int kTile = 16;  ///< image tiles [px] that get their own geom culling

// Calls f(u, v) for every pixel, tile by tile, after culling the caster's geoms to the tile's view cone.
template <typename F>
void forEachPixelByTile(RayCaster& caster, const SensorPose& pose, const Intrinsics& k, int width, int height,
                        double range, F&& f) {
  for (int v0 = 0; v0 < height; v0 += kTile)
    for (int u0 = 0; u0 < width; u0 += kTile) {
      const int u1 = std::min(width, u0 + kTile), v1 = std::min(height, v0 + kTile);
      const Eigen::Vector3d centre =
          Eigen::Vector3d((0.5 * (u0 + u1 - 1) - k.cx) / k.fx, (0.5 * (v0 + v1 - 1) - k.cy) / k.fy, 1.0).normalized();
      double half = 0.0;
      for (int cu : {u0, u1 - 1})
        for (int cv : {v0, v1 - 1}) {
          const Eigen::Vector3d c = Eigen::Vector3d((cu - k.cx) / k.fx, (cv - k.cy) / k.fy, 1.0).normalized();
          half = std::max(half, std::acos(std::min(1.0, c.dot(centre))));
        }
      caster.prepare(pose.origin, range, pose.rotation * centre, half + 1e-6);
      for (int v = v0; v < v1; ++v)
        for (int u = u0; u < u1; ++u) f(u, v);
    }
}

}  // namespace

DepthImage simulateDepth(RayCaster& caster, const SensorPose& pose, const DepthCameraSpec& s, std::mt19937& rng) {
  const Intrinsics k = intrinsics(s);
  DepthImage img;
  img.width = s.width;
  img.height = s.height;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  img.points.assign(static_cast<size_t>(s.width) * s.height, Eigen::Vector3f(nan, nan, nan));
  std::normal_distribution<double> unit(0.0, 1.0);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  forEachPixelByTile(caster, pose, k, s.width, s.height, s.range_max_m, [&](int u, int v) {
    const Eigen::Vector3d ray((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);  // z = 1
    const double len = ray.norm();
    const Eigen::Vector3d dir = pose.rotation * (ray / len);
    int g = -1;
    const double d = caster.cast(pose.origin, dir, &g);
    if (d < 0.0) return;
    const double z = d / len;
    if (z < s.range_min_m || z > s.range_max_m) return;
    if (s.dropout > 0 && uni(rng) < s.dropout) return;
    const Eigen::Vector3d n = caster.normal(g, pose.origin + d * dir, dir);
    if (std::acos(std::min(1.0, -n.dot(dir))) > s.grazing_limit_rad) return;
    const double zn = z + (s.noise_coeff > 0 ? s.noise_coeff * z * z * unit(rng) : 0.0);
    img.points[static_cast<size_t>(v) * s.width + u] = (ray * zn).cast<float>();
  });
  return img;
}

ColorImage simulateColor(RayCaster& caster, const mjModel* model, const SensorPose& pose, const ColorCameraSpec& s) {
  const Intrinsics k = intrinsics(s);
  ColorImage img;
  img.width = s.width;
  img.height = s.height;
  img.rgb.resize(static_cast<size_t>(s.width) * s.height * 3);
  forEachPixelByTile(caster, pose, k, s.width, s.height, s.range_max_m, [&](int u, int v) {
    const Eigen::Vector3d dir = pose.rotation * Eigen::Vector3d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0).normalized();
    int g = -1;
    const double d = caster.cast(pose.origin, dir, &g);
    uint8_t* px = &img.rgb[(static_cast<size_t>(v) * s.width + u) * 3];
    for (int c = 0; c < 3; ++c)
      px[c] = (d < 0.0 || d > s.range_max_m) ? s.background[c]
                                             : static_cast<uint8_t>(std::lround(255.0 * model->geom_rgba[4 * g + c]));
  });
  return img;
}

}  // namespace thorvald_sim

namespace thorvald_sim {

ImuReading simulateImu(const mjModel* model, const mjData* data, int body, const Eigen::Matrix3d& mount,
                       const ImuSpec& spec, std::mt19937& rng, ImuErrors* errors, double t_s) {
  mjtNum vel[6], acc[6];
  mj_objectVelocity(model, data, mjOBJ_BODY, body, vel, 1);      // [angular; linear] in the body frame
  mj_objectAcceleration(model, data, mjOBJ_BODY, body, acc, 1);  // includes the gravity reaction
  const Eigen::Quaterniond qb(data->xquat[4 * body], data->xquat[4 * body + 1], data->xquat[4 * body + 2],
                              data->xquat[4 * body + 3]);
  ImuReading r;
  r.orientation = qb * Eigen::Quaterniond(mount);
  const Eigen::Vector3d gyro = mount.transpose() * Eigen::Vector3d(vel[0], vel[1], vel[2]);
  const Eigen::Vector3d accel = mount.transpose() * Eigen::Vector3d(acc[3], acc[4], acc[5]);
  if (spec.realism == Realism::kDatasheet) {
    if (!errors) throw std::invalid_argument("simulateImu: the datasheet profile needs the sensor's ImuErrors");
    r.angular_velocity = gyro, r.linear_acceleration = accel;
    errors->apply(t_s, &r.angular_velocity, &r.linear_acceleration, rng);
    return r;
  }
  std::normal_distribution<double> unit(0.0, 1.0);
  auto noisy = [&](const Eigen::Vector3d& v, double sd) {
    return sd > 0 ? Eigen::Vector3d(v + sd * Eigen::Vector3d(unit(rng), unit(rng), unit(rng))) : v;
  };
  r.angular_velocity = noisy(gyro, spec.gyro_noise_radps);
  r.linear_acceleration = noisy(accel, spec.accel_noise_mps2);
  return r;
}

}  // namespace thorvald_sim
