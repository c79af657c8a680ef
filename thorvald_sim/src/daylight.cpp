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

namespace {

/// The sun's camera for the square of half side `half_extent_m` around `centre` at `size` pixels across, plus
/// `extra_px` pixels on every side.
ShadowMap sunView(const Daylight& light, const Eigen::Vector3d& centre, double half_extent_m, int size, int extra_px) {
  ShadowMap s;
  const Eigen::Vector3d to_sun = light.toSun();
  const Eigen::Vector3d z = -to_sun;
  Eigen::Vector3d x = z.cross(Eigen::Vector3d::UnitZ());
  if (x.norm() < 1e-6) x = Eigen::Vector3d::UnitX();
  x.normalize();
  s.pose.origin = centre + kSunDistanceM * to_sun;
  s.pose.rotation.col(0) = x;
  s.pose.rotation.col(1) = z.cross(x);
  s.pose.rotation.col(2) = z;
  const int full = size + 2 * extra_px;
  s.view.width = s.view.height = full;
  const double f = 0.5 * size * kSunDistanceM / half_extent_m;
  s.view.k = Intrinsics{f, f, 0.5 * (full - 1), 0.5 * (full - 1)};
  const double reach = half_extent_m * (1.0 + 2.0 * extra_px / size);
  s.view.near_m = kSunDistanceM - 4.0 * reach - 3.0;
  s.view.far_m = kSunDistanceM + 4.0 * reach + 3.0;
  return s;
}

/// Renders `s.view` in bands of rows that fit the renderer's buffer into s.depth.
void renderInBands(CameraRenderer* renderer, const mjData* data, int own_root_body, ShadowMap* s) {
  const int band = std::max(1, renderer->maxHeight());
  if (s->view.height <= band) {
    renderer->render(data, s->pose, s->view, own_root_body, &s->depth);
    return;
  }
  RenderedView part;
  s->depth.width = s->view.width, s->depth.height = s->view.height;
  s->depth.depth_m.resize(static_cast<size_t>(s->view.width) * s->view.height);
  s->depth.geom.resize(s->depth.depth_m.size());
  for (int v0 = 0; v0 < s->view.height; v0 += band) {
    CameraView view = s->view;
    view.height = std::min(band, s->view.height - v0);
    view.k.cy -= v0;
    renderer->render(data, s->pose, view, own_root_body, &part);
    std::copy(part.depth_m.begin(), part.depth_m.end(),
              s->depth.depth_m.begin() + static_cast<size_t>(v0) * view.width);
    std::copy(part.geom.begin(), part.geom.end(), s->depth.geom.begin() + static_cast<size_t>(v0) * view.width);
  }
}

bool sameSun(const Daylight& a, const Daylight& b) {
  return a.sunny == b.sunny && a.sun_elevation_rad == b.sun_elevation_rad && a.sun_azimuth_rad == b.sun_azimuth_rad;
}

}  // namespace

ShadowMap renderShadowMap(CameraRenderer* renderer, const mjData* data, const Daylight& light,
                          const Eigen::Vector3d& centre, double half_extent_m, int size, int own_root_body) {
  if (!light.sunny) return ShadowMap();
  ShadowMap s = sunView(light, centre, half_extent_m, size, 0);
  renderer->render(data, s.pose, s.view, own_root_body, &s.depth);
  s.valid = true;
  return s;
}

const ShadowMap& ShadowMapCache::get(CameraRenderer* renderer, const mjModel* model, const mjData* data,
                                     const Daylight& light, const Eigen::Vector3d& centre, double half_extent_m,
                                     int size, int own_root_body) {
  if (!light.sunny) {
    map_ = ShadowMap();
    return map_;
  }
  if (map_.valid && holds(model, data, light, centre, half_extent_m, size, own_root_body)) return map_;
  const int extra = static_cast<int>(std::ceil(margin_m_ * size / (2.0 * half_extent_m)));
  map_ = sunView(light, centre, half_extent_m, size, std::min(extra, (renderer->maxWidth() - size) / 2));
  renderInBands(renderer, data, own_root_body, &map_);
  map_.valid = true;
  ++renders_;
  light_ = light, centre_ = centre, half_extent_m_ = half_extent_m, size_ = size, own_root_body_ = own_root_body;
  remember(model, data, own_root_body);
  return map_;
}

bool ShadowMapCache::holds(const mjModel* m, const mjData* data, const Daylight& light, const Eigen::Vector3d& centre,
                           double half_extent_m, int size, int own_root_body) const {
  if (!sameSun(light, light_) || half_extent_m != half_extent_m_ || size != size_ || own_root_body != own_root_body_)
    return false;
  // The asked square in the map's plane, within the rendered one.
  const Eigen::Vector3d d = map_.pose.rotation.transpose() * (centre - centre_);
  const double slack = half_extent_m * (static_cast<double>(map_.view.width) / size - 1.0);
  if (std::fabs(d.x()) > slack || std::fabs(d.y()) > slack || std::fabs(d.z()) > slack) return false;
  constexpr double kMoved = 5e-4, kTurned = 5e-3;  // [m], [rad]: below the map's pixel (5.8 mm for the rover)
  size_t k = 0;
  for (int g = 0; g < m->ngeom; ++g) {
    if (own_root_body >= 0 && m->body_rootid[m->geom_bodyid[g]] == own_root_body) continue;
    for (int i = 0; i < 3; ++i)
      if (std::fabs(data->geom_xpos[3 * g + i] - geoms_[k++]) > kMoved) return false;
    for (int i = 0; i < 9; ++i)
      if (std::fabs(data->geom_xmat[9 * g + i] - geoms_[k++]) > kTurned) return false;
    if ((m->geom_rgba[4 * g + 3] == 0.0f) != (geoms_[k++] == 0.0)) return false;
  }
  return true;
}

void ShadowMapCache::remember(const mjModel* m, const mjData* data, int own_root_body) {
  geoms_.clear();
  for (int g = 0; g < m->ngeom; ++g) {
    if (own_root_body >= 0 && m->body_rootid[m->geom_bodyid[g]] == own_root_body) continue;
    geoms_.insert(geoms_.end(), data->geom_xpos + 3 * g, data->geom_xpos + 3 * g + 3);
    geoms_.insert(geoms_.end(), data->geom_xmat + 9 * g, data->geom_xmat + 9 * g + 9);
    geoms_.push_back(m->geom_rgba[4 * g + 3]);
  }
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

namespace {

/// std::floor without the library call (exact for |x| < 2^52: world points over a millimetre lattice).
inline double floorOf(double x) {
  const double t = static_cast<double>(static_cast<int64_t>(x));
  return t > x ? t - 1.0 : t;
}

/// valueNoise with the lattice values of the last cell kept: neighbouring pixels mostly fall in the same cell.
class CachedValueNoise {
 public:
  explicit CachedValueNoise(double cell_m) : per_m_(1.0 / cell_m) {}
  double operator()(const Eigen::Vector3d& p) {
    const Eigen::Vector3d c = p * per_m_;  // p / cell up to an ulp
    const Eigen::Vector3d f(floorOf(c.x()), floorOf(c.y()), floorOf(c.z()));
    const Eigen::Vector3d t = c - f;
    const Eigen::Vector3d s = t.array() * t.array() * (3.0 - 2.0 * t.array());  // smoothstep
    const int64_t x = static_cast<int64_t>(f.x()), y = static_cast<int64_t>(f.y()), z = static_cast<int64_t>(f.z());
    if (!valid_ || x != x_ || y != y_ || z != z_) {
      for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j)
          for (int l = 0; l < 2; ++l) corner_[i][j][l] = latticeValue(x + i, y + j, z + l);
      x_ = x, y_ = y, z_ = z, valid_ = true;
    }
    auto lerp = [](double a, double b, double w) { return a + (b - a) * w; };
    const double y0 =
        lerp(lerp(corner_[0][0][0], corner_[1][0][0], s.x()), lerp(corner_[0][1][0], corner_[1][1][0], s.x()), s.y());
    const double y1 =
        lerp(lerp(corner_[0][0][1], corner_[1][0][1], s.x()), lerp(corner_[0][1][1], corner_[1][1][1], s.x()), s.y());
    return lerp(y0, y1, s.z());
  }

 private:
  double per_m_;
  bool valid_ = false;
  int64_t x_ = 0, y_ = 0, z_ = 0;
  double corner_[2][2][2] = {};
};

/// The surface points of three image rows (v - 1, v, v + 1) in the optical frame (NaN where nothing is seen).
class PointRows {
 public:
  PointRows(const RenderedView& view, const Intrinsics& k)
      : view_(view), k_(k), inv_fx_(1.0 / k.fx), inv_fy_(1.0 / k.fy), rows_(3 * view.width) {}
  /// Makes rows v - 1 .. v + 1 available (called with v = 0, 1, 2, ...).
  void advance(int v) {
    for (int r = v == 0 ? -1 : v + 1; r <= v + 1; ++r) {
      if (r < 0 || r >= view_.height) continue;
      Eigen::Vector3d* row = &rows_[static_cast<size_t>((r + 3) % 3) * view_.width];
      const float* z = &view_.depth_m[static_cast<size_t>(r) * view_.width];
      const double y = (r - k_.cy) * inv_fy_;
      for (int u = 0; u < view_.width; ++u)
        row[u] = std::isfinite(z[u]) ? Eigen::Vector3d(z[u] * ((u - k_.cx) * inv_fx_), z[u] * y, z[u])
                                     : Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
    }
  }
  const Eigen::Vector3d& at(int u, int v) const { return rows_[static_cast<size_t>((v + 3) % 3) * view_.width + u]; }

 private:
  const RenderedView& view_;
  const Intrinsics& k_;
  double inv_fx_, inv_fy_;
  std::vector<Eigen::Vector3d> rows_;
};

/// The surface normal at (u, v) in the optical frame from its neighbours on the same geom (points of `rows`),
/// facing the camera.
Eigen::Vector3d normalFromRows(const RenderedView& view, const PointRows& rows, int u, int v,
                               const Eigen::Vector3d& p) {
  const int g = view.geom[static_cast<size_t>(v) * view.width + u];
  auto neighbour = [&](int du, int dv) -> const Eigen::Vector3d& {
    const int nu = u + du, nv = v + dv;
    if (nu < 0 || nv < 0 || nu >= view.width || nv >= view.height ||
        view.geom[static_cast<size_t>(nv) * view.width + nu] != g)
      return p;
    const Eigen::Vector3d& q = rows.at(nu, nv);
    return q.allFinite() ? q : p;
  };
  const Eigen::Vector3d dx = neighbour(1, 0) - neighbour(-1, 0), dy = neighbour(0, 1) - neighbour(0, -1);
  Eigen::Vector3d n = dy.cross(dx);
  if (!(n.norm() > 1e-12)) return -p.normalized();
  n.normalize();
  return n.dot(p) > 0.0 ? -n : n;
}

/// litBySun with the map's transform and scale taken out of the pixel loop (one division per point).
class SunLookup {
 public:
  SunLookup(const ShadowMap& s, double bias_m)
      : s_(s), rt_(s.pose.rotation.transpose()), rt_origin_(rt_ * s.pose.origin), bias_m_(bias_m) {}
  bool lit(const Eigen::Vector3d& p) const {
    if (!s_.valid) return true;
    const Eigen::Vector3d q = rt_ * p - rt_origin_;
    if (!(q.z() > 0.0)) return true;
    const double inv_z = 1.0 / q.z();
    const double x = s_.view.k.fx * q.x() * inv_z + s_.view.k.cx, y = s_.view.k.fy * q.y() * inv_z + s_.view.k.cy;
    if (!(x > -0.5 && y > -0.5 && x < s_.depth.width - 0.5 && y < s_.depth.height - 0.5)) return true;
    const int u = static_cast<int>(x + 0.5), v = static_cast<int>(y + 0.5);  // nearest pixel, as lround
    const float d = s_.depth.depth_m[static_cast<size_t>(v) * s_.depth.width + u];
    return !std::isfinite(d) || d >= q.z() - bias_m_;
  }

 private:
  const ShadowMap& s_;
  const Eigen::Matrix3d rt_;
  const Eigen::Vector3d rt_origin_;
  const double bias_m_;
};

/// std::lround of a non-negative x, clamped to a byte (x - trunc(x) is exact in double).
uint8_t roundToByte(double x) {
  if (!(x > 0.0)) return 0;
  if (x >= 255.0) return 255;
  const int r = static_cast<int>(x);
  return static_cast<uint8_t>(x - r >= 0.5 ? r + 1 : r);
}

}  // namespace

void shadeDaylight(const RenderedView& view, const SensorPose& pose, const Intrinsics& k, const Daylight& light,
                   const ShadowMap* shadow, const std::vector<float>& texture, ColorImage* rgb) {
  if (rgb->width != view.width || rgb->height != view.height) return;
  const Eigen::Vector3d sun_cam = pose.rotation.transpose() * light.toSun();
  const bool use_shadow = light.sunny && shadow;
  static const ShadowMap kNoShadow;
  const SunLookup sun_map(use_shadow ? *shadow : kNoShadow, light.shadow_bias_m);
  PointRows rows(view, k);
  CachedValueNoise fine(0.004), coarse(0.02);
  for (int v = 0; v < view.height; ++v) {
    rows.advance(v);
    for (int u = 0; u < view.width; ++u) {
      const size_t i = static_cast<size_t>(v) * view.width + u;
      const int g = view.geom[i];
      if (g < 0) continue;
      const Eigen::Vector3d& p = rows.at(u, v);
      if (!p.allFinite()) continue;
      const Eigen::Vector3d world = pose.origin + pose.rotation * p;
      const bool lit = !use_shadow || sun_map.lit(world);
      const double lambert = lit ? std::max(0.0, normalFromRows(view, rows, u, v, p).dot(sun_cam)) : 0.0;
      const double amp = g < static_cast<int>(texture.size()) ? texture[g] : 0.0;
      const double tex = amp > 0.0 ? 1.0 + amp * (0.6 * fine(world) + 0.4 * coarse(world)) : 1.0;
      const double gain = tex * (light.ambient + (lit ? light.direct * lambert : 0.0)) * light.exposure;
      uint8_t* px = &rgb->rgb[3 * i];
      for (int c = 0; c < 3; ++c) px[c] = roundToByte(px[c] * gain);
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
