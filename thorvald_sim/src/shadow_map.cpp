// The sun's shadow map of daylight.h: a depth view rendered from far along the sun's direction (in bands when taller
// than the renderer's buffer), the cache that keeps it while the scene and the region hold, and the lit test.
#include <algorithm>
#include <cmath>

#include "thorvald_sim/daylight.h"

namespace thorvald_sim {

namespace {

constexpr double kSunDistanceM = 20.0;  ///< the shadow map's camera this far from the region, towards the sun

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

}  // namespace thorvald_sim
