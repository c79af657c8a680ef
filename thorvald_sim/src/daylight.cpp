#include "thorvald_sim/daylight.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace thorvald_sim {

namespace {

constexpr double kSunDistanceM = 20.0;  ///< the shadow map's camera this far from the region, towards the sun

double latticeValue(int64_t x, int64_t y, int64_t z) {
  uint64_t h = static_cast<uint64_t>(x) * 0x9E3779B97F4A7C15ull ^ static_cast<uint64_t>(y) * 0xC2B2AE3D27D4EB4Full ^
               static_cast<uint64_t>(z) * 0x165667B19E3779F9ull;
  h ^= h >> 29;
  h *= 0xBF58476D1CE4E5B9ull;
  h ^= h >> 32;
  return static_cast<double>(h & 0xFFFFFF) / static_cast<double>(0x800000) - 1.0;
}

/// The pixel's surface point in the optical frame (NaN where nothing is seen).
Eigen::Vector3d pointAt(const RenderedView& view, const Intrinsics& k, int u, int v) {
  const float z = view.depth_m[static_cast<size_t>(v) * view.width + u];
  if (!std::isfinite(z)) return Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  return {z * (u - k.cx) / k.fx, z * (v - k.cy) / k.fy, z};
}

/// The surface normal at (u, v) in the optical frame from the neighbours on the same geom, facing the camera.
Eigen::Vector3d normalAt(const RenderedView& view, const Intrinsics& k, int u, int v, const Eigen::Vector3d& p) {
  const int g = view.geom[static_cast<size_t>(v) * view.width + u];
  auto neighbour = [&](int du, int dv) -> Eigen::Vector3d {
    const int nu = u + du, nv = v + dv;
    if (nu < 0 || nv < 0 || nu >= view.width || nv >= view.height ||
        view.geom[static_cast<size_t>(nv) * view.width + nu] != g)
      return p;
    const Eigen::Vector3d q = pointAt(view, k, nu, nv);
    return q.allFinite() ? q : p;
  };
  const Eigen::Vector3d dx = neighbour(1, 0) - neighbour(-1, 0), dy = neighbour(0, 1) - neighbour(0, -1);
  Eigen::Vector3d n = dy.cross(dx);
  if (!(n.norm() > 1e-12)) return -p.normalized();
  n.normalize();
  return n.dot(p) > 0.0 ? -n : n;
}

}  // namespace

Eigen::Vector3d Daylight::toSun() const {
  return {std::cos(sun_elevation_rad) * std::cos(sun_azimuth_rad),
          std::cos(sun_elevation_rad) * std::sin(sun_azimuth_rad), std::sin(sun_elevation_rad)};
}

Daylight sunnyDaylight(double elevation_rad, double azimuth_rad) {
  Daylight d;
  d.sun_elevation_rad = elevation_rad;
  d.sun_azimuth_rad = azimuth_rad;
  return d;
}

Daylight overcastDaylight(double elevation_rad, double azimuth_rad) {
  Daylight d = sunnyDaylight(elevation_rad, azimuth_rad);
  d.sunny = false;
  d.ambient = 0.9;
  d.direct = 0.1;
  return d;
}

Daylight randomDaylight(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const bool sunny = u(rng) < 0.6;
  const double elevation = (30.0 + 40.0 * u(rng)) * M_PI / 180.0, azimuth = 2.0 * M_PI * u(rng);
  Daylight d = sunny ? sunnyDaylight(elevation, azimuth) : overcastDaylight(elevation, azimuth);
  d.exposure = 0.9 + 0.2 * u(rng);
  return d;
}

ShadowMap renderShadowMap(CameraRenderer* renderer, const mjData* data, const Daylight& light,
                          const Eigen::Vector3d& centre, double half_extent_m, int size, int own_root_body) {
  ShadowMap s;
  if (!light.sunny) return s;
  const Eigen::Vector3d to_sun = light.toSun();
  const Eigen::Vector3d z = -to_sun;
  Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ());
  if (x.norm() < 1e-6) x = Eigen::Vector3d::UnitX();
  x.normalize();
  s.pose.origin = centre + kSunDistanceM * to_sun;
  s.pose.rotation.col(0) = x;
  s.pose.rotation.col(1) = z.cross(x);
  s.pose.rotation.col(2) = z;
  s.view.width = s.view.height = size;
  const double f = 0.5 * size * kSunDistanceM / half_extent_m;
  s.view.k = Intrinsics{f, f, 0.5 * (size - 1), 0.5 * (size - 1)};
  s.view.near_m = kSunDistanceM - 4.0 * half_extent_m - 3.0;
  s.view.far_m = kSunDistanceM + 4.0 * half_extent_m + 3.0;
  renderer->render(data, s.pose, s.view, own_root_body, &s.depth);
  s.valid = true;
  return s;
}

bool litBySun(const ShadowMap& s, const Eigen::Vector3d& p, double bias_m) {
  if (!s.valid) return true;
  const Eigen::Vector3d q = s.pose.rotation.transpose() * (p - s.pose.origin);
  if (!(q.z() > 0.0)) return true;
  const int u = static_cast<int>(std::lround(s.view.k.fx * q.x() / q.z() + s.view.k.cx));
  const int v = static_cast<int>(std::lround(s.view.k.fy * q.y() / q.z() + s.view.k.cy));
  if (u < 0 || v < 0 || u >= s.depth.width || v >= s.depth.height) return true;
  const float d = s.depth.depth_m[static_cast<size_t>(v) * s.depth.width + u];
  return !std::isfinite(d) || d >= q.z() - bias_m;
}

double valueNoise(const Eigen::Vector3d& p, double cell_m) {
  const Eigen::Vector3d c = p / cell_m;
  const Eigen::Vector3d f = c.array().floor();
  const Eigen::Vector3d t = c - f;
  const Eigen::Vector3d s = t.array() * t.array() * (3.0 - 2.0 * t.array());  // smoothstep
  const int64_t x = static_cast<int64_t>(f.x()), y = static_cast<int64_t>(f.y()), z = static_cast<int64_t>(f.z());
  double corner[2][2][2];
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j)
      for (int l = 0; l < 2; ++l) corner[i][j][l] = latticeValue(x + i, y + j, z + l);
  auto lerp = [](double a, double b, double w) { return a + (b - a) * w; };
  const double y0 =
      lerp(lerp(corner[0][0][0], corner[1][0][0], s.x()), lerp(corner[0][1][0], corner[1][1][0], s.x()), s.y());
  const double y1 =
      lerp(lerp(corner[0][0][1], corner[1][0][1], s.x()), lerp(corner[0][1][1], corner[1][1][1], s.x()), s.y());
  return lerp(y0, y1, s.z());
}

void shadeDaylight(const RenderedView& view, const SensorPose& pose, const Intrinsics& k, const Daylight& light,
                   const ShadowMap* shadow, const std::vector<float>& texture, ColorImage* rgb) {
  if (rgb->width != view.width || rgb->height != view.height) return;
  const Eigen::Vector3d sun_cam = pose.rotation.transpose() * light.toSun();
  for (int v = 0; v < view.height; ++v) {
    for (int u = 0; u < view.width; ++u) {
      const size_t i = static_cast<size_t>(v) * view.width + u;
      const int g = view.geom[i];
      if (g < 0) continue;
      const Eigen::Vector3d p = pointAt(view, k, u, v);
      if (!p.allFinite()) continue;
      const Eigen::Vector3d world = pose.origin + pose.rotation * p;
      const double lambert = std::max(0.0, normalAt(view, k, u, v, p).dot(sun_cam));
      const bool lit = !light.sunny || !shadow || litBySun(*shadow, world, light.shadow_bias_m);
      const double amp = g < static_cast<int>(texture.size()) ? texture[g] : 0.0;
      const double tex = amp > 0.0 ? 1.0 + amp * (0.6 * valueNoise(world, 0.004) + 0.4 * valueNoise(world, 0.02)) : 1.0;
      const double gain = tex * (light.ambient + (lit ? light.direct * lambert : 0.0)) * light.exposure;
      uint8_t* px = &rgb->rgb[3 * i];
      for (int c = 0; c < 3; ++c) px[c] = static_cast<uint8_t>(std::clamp(std::lround(px[c] * gain), 0L, 255L));
    }
  }
}

float cottonGeomTexture(const std::string& name) {
  const auto starts = [&name](const char* prefix) { return name.rfind(prefix, 0) == 0; };
  const auto has = [&name](const char* part) { return name.find(part) != std::string::npos; };
  if (name == "ground" || starts("clod")) return 0.35f;
  if (!starts("plant") && !starts("weed")) return 0.0f;
  if (has("_bract") || has("_burr") || has("_dry")) return 0.25f;
  if (has("_leaf") || starts("weed")) return 0.18f;
  if (has("_boll")) return 0.12f;  // lobes and core: fluffy fibre
  return 0.1f;                     // stems, branches, pots
}

}  // namespace thorvald_sim
