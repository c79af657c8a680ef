#include "thorvald_sim/daylight.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace thorvald_sim {

namespace {

// The texture's lattice: a point (x, y, z) of the integer lattice gets the value latticeMix(x kHashX ^ y kHashY ^
// z kHashZ) (32-bit arithmetic), uniform in [-1, 1) in steps of 2^-23 (24 bits of the mixed hash, exact in a float).
constexpr uint32_t kHashX = 0x8DA6B343u, kHashY = 0xD8163841u, kHashZ = 0xCB1AB31Fu;

inline float latticeMix(uint32_t h) {  // lowbias32 (C. Wellons' hash prospector)
  h ^= h >> 16;
  h *= 0x7FEB352Du;
  h ^= h >> 15;
  h *= 0x846CA68Bu;
  h ^= h >> 16;
  return static_cast<float>(static_cast<int32_t>(h >> 8) - 0x800000) * (1.0f / 0x800000);
}

double latticeValue(int64_t x, int64_t y, int64_t z) {
  return latticeMix(static_cast<uint32_t>(x) * kHashX ^ static_cast<uint32_t>(y) * kHashY ^
                    static_cast<uint32_t>(z) * kHashZ);
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

/// One octave of the texture (valueNoise of cell `cell_m`) over an image row, in float: a point is given by its
/// offset d from the camera's origin o (world axes); in cells it is d / cell + the origin's place in its cell, and
/// the lattice is counted from the origin's cell (so the float keeps its precision however far o is from the
/// world's origin).
struct NoiseOctave {
  NoiseOctave(const Eigen::Vector3d& origin, double cell_m) : per_m(static_cast<float>(1.0 / cell_m)) {
    for (int a = 0; a < 3; ++a) {
      const double c = origin[a] / cell_m, f = std::floor(c);
      off[a] = static_cast<float>(c - f);
      base[a] = static_cast<uint32_t>(static_cast<int64_t>(f)) * kHash[a];
    }
  }
  /// Along axis a, for the offset d: the smoothstep weight within the cell and the hash term of the cell's lower
  /// lattice point.
  void axis(float d, int a, float* s, uint32_t* h) const {
    constexpr float kMax = 1e6f;  // [cells] beyond this (4 km of the camera) the point is treated as at 0
    float c = d * per_m + off[a];
    c = (c > -kMax) & (c < kMax) ? c : 0.0f;  // NaN too
    int cell = static_cast<int>(c);
    cell -= static_cast<float>(cell) > c;  // floor
    const float t = c - static_cast<float>(cell);
    *s = t * t * (3.0f - 2.0f * t);  // smoothstep
    *h = base[a] + static_cast<uint32_t>(cell) * kHash[a];
  }

  static constexpr uint32_t kHash[3] = {kHashX, kHashY, kHashZ};
  float per_m;
  float off[3];
  uint32_t base[3];
};

// AVX2 clones of the two vectorised row loops where the target has them (x86-64); one plain version elsewhere (e.g.
// the rover's ARM computer).
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define THORVALD_SIM_AVX2_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define THORVALD_SIM_AVX2_CLONES
#endif

/// out[i] = the octave's noise at offsets (dx[i], dy[i], dz[i]), i < n (0 for NaN offsets). Branch-free, so that the
/// compiler vectorises it (also for AVX2, chosen at run time: the same float operations, the same result).
THORVALD_SIM_AVX2_CLONES void noiseRow(const NoiseOctave& o, const float* dx, const float* dy, const float* dz, int n,
                                       float* out) {
  for (int i = 0; i < n; ++i) {
    float sx, sy, sz;
    uint32_t x0, y0, z0;
    o.axis(dx[i], 0, &sx, &x0);
    o.axis(dy[i], 1, &sy, &y0);
    o.axis(dz[i], 2, &sz, &z0);
    const uint32_t x1 = x0 + kHashX, y1 = y0 + kHashY, z1 = z0 + kHashZ;
    auto lerp = [](float a, float b, float w) { return a + (b - a) * w; };
    const float c00 = lerp(latticeMix(x0 ^ y0 ^ z0), latticeMix(x1 ^ y0 ^ z0), sx);
    const float c10 = lerp(latticeMix(x0 ^ y1 ^ z0), latticeMix(x1 ^ y1 ^ z0), sx);
    const float c01 = lerp(latticeMix(x0 ^ y0 ^ z1), latticeMix(x1 ^ y0 ^ z1), sx);
    const float c11 = lerp(latticeMix(x0 ^ y1 ^ z1), latticeMix(x1 ^ y1 ^ z1), sx);
    out[i] = lerp(lerp(c00, c10, sy), lerp(c01, c11, sy), sz);
  }
}

/// The working rows of shadeDaylight: the surface points of image rows v - 1, v, v + 1 (optical frame, NaN where
/// nothing is seen) and their geoms, each padded by one pixel on either side (geom -2 there and outside the image),
/// and the per-pixel terms of row v.
struct ShadeRows {
  int w = 0;
  std::vector<float> x[3], y[3], z[3];
  std::vector<int> g[3];
  std::vector<float> ray_x;  ///< (u - cx) / fx per column
  std::vector<float> lambert, dx, dy, dz, fine, coarse, lit, sun_depth, gain;
  std::vector<int> sun_pixel;

  explicit ShadeRows(int width) : w(width) {
    for (int r = 0; r < 3; ++r) {
      x[r].assign(w + 2, 0.0f), y[r].assign(w + 2, 0.0f), z[r].assign(w + 2, 0.0f);
      g[r].assign(w + 2, -2);
    }
    for (auto* v : {&lambert, &dx, &dy, &dz, &fine, &coarse, &lit, &sun_depth, &gain}) v->assign(w, 0.0f);
    sun_pixel.assign(w, 0);
  }
  /// Slot of image row r in the ring.
  static int slot(int r) { return (r + 3) % 3; }
  /// Fills the slot of image row r (-1 and height: nothing seen).
  void load(const RenderedView& view, const Intrinsics& k, int r) {
    const int s = slot(r);
    if (r < 0 || r >= view.height) {
      std::fill(g[s].begin(), g[s].end(), -2);
      std::fill(z[s].begin(), z[s].end(), std::numeric_limits<float>::quiet_NaN());
      return;
    }
    const float* depth = &view.depth_m[static_cast<size_t>(r) * w];
    std::copy(view.geom.begin() + static_cast<size_t>(r) * w, view.geom.begin() + static_cast<size_t>(r + 1) * w,
              g[s].begin() + 1);
    const float ry = static_cast<float>((r - k.cy) / k.fy);
    float *px = &x[s][1], *py = &y[s][1], *pz = &z[s][1];
    for (int u = 0; u < w; ++u) {
      const float d = std::fabs(depth[u]) <= std::numeric_limits<float>::max()
                          ? depth[u]
                          : std::numeric_limits<float>::quiet_NaN();  // NaN where infinite
      px[u] = d * ray_x[u], py[u] = d * ry, pz[u] = d;
    }
  }
};

/// Lambert's cosine max(0, n . sun) for each pixel u of the row in slot `here` (out[u]), n the surface normal from its
/// four neighbours on the same geom (the pixel itself where there is none), facing the camera. Branch-free: every
/// load and both quotients unconditional, the choices selects, so that it vectorises (AVX2 as noiseRow).
THORVALD_SIM_AVX2_CLONES void lambertRow(const ShadeRows& rows, int above, int here, int below,
                                         const Eigen::Vector3f& sun, float* out) {
  const int w = rows.w;
  const float *x0 = rows.x[above].data(), *y0 = rows.y[above].data(), *z0 = rows.z[above].data();
  const float *x1 = rows.x[here].data(), *y1 = rows.y[here].data(), *z1 = rows.z[here].data();
  const float *x2 = rows.x[below].data(), *y2 = rows.y[below].data(), *z2 = rows.z[below].data();
  const int *g0 = rows.g[above].data(), *g1 = rows.g[here].data(), *g2 = rows.g[below].data();
  const float sx = sun.x(), sy = sun.y(), sz = sun.z();
  for (int i = 1; i <= w; ++i) {
    const int g = g1[i];
    const float px = x1[i], py = y1[i], pz = z1[i];
    // A neighbour counts when it sees the same geom at a finite depth.
    const bool r = (g1[i + 1] == g) & (z1[i + 1] == z1[i + 1]), l = (g1[i - 1] == g) & (z1[i - 1] == z1[i - 1]);
    const bool d = (g2[i] == g) & (z2[i] == z2[i]), a = (g0[i] == g) & (z0[i] == z0[i]);
    const float x_r = x1[i + 1], y_r = y1[i + 1], x_l = x1[i - 1], y_l = y1[i - 1];
    const float x_d = x2[i], y_d = y2[i], x_a = x0[i], y_a = y0[i];
    const float rx = r ? x_r : px, ry = r ? y_r : py, rz = r ? z1[i + 1] : pz;
    const float lx = l ? x_l : px, ly = l ? y_l : py, lz = l ? z1[i - 1] : pz;
    const float dnx = d ? x_d : px, dny = d ? y_d : py, dnz = d ? z2[i] : pz;
    const float upx = a ? x_a : px, upy = a ? y_a : py, upz = a ? z0[i] : pz;
    const float ax = rx - lx, ay = ry - ly, az = rz - lz;                                // along the row
    const float bx = dnx - upx, by = dny - upy, bz = dnz - upz;                          // down the column
    const float nx = by * az - bz * ay, ny = bz * ax - bx * az, nz = bx * ay - by * ax;  // b x a
    const float nn = std::sqrt(nx * nx + ny * ny + nz * nz), pn = std::sqrt(px * px + py * py + pz * pz);
    const float ns = nx * sx + ny * sy + nz * sz, np = nx * px + ny * py + nz * pz;
    const float facing = (np > 0.0f ? -ns : ns) / nn;
    const float towards_camera = -(px * sx + py * sy + pz * sz) / pn;  // no normal (a lone pixel): facing the camera
    const float cosine = nn > 1e-12f ? facing : towards_camera;
    out[i - 1] = cosine > 0.0f ? cosine : 0.0f;
  }
}

/// litBySun in float for a row of points of the camera's optical frame: the sun's camera sees p at q = M p + b.
class SunLookup {
 public:
  SunLookup(const ShadowMap& s, const SensorPose& camera, double bias_m) : s_(s), bias_m_(static_cast<float>(bias_m)) {
    const Eigen::Matrix3d rt = s.pose.rotation.transpose();
    m_ = (rt * camera.rotation).cast<float>();
    b_ = (rt * (camera.origin - s.pose.origin)).cast<float>();
    fx_ = static_cast<float>(s.view.k.fx), fy_ = static_cast<float>(s.view.k.fy);
    cx_ = static_cast<float>(s.view.k.cx), cy_ = static_cast<float>(s.view.k.cy);
  }
  /// lit[i] = 1 where the point (x[i], y[i], z[i]) is lit (or outside the map), else 0, for i < n; `pixel` is scratch.
  void row(const float* x, const float* y, const float* z, int n, int* pixel, float* depth, float* lit) const {
    const int w = s_.depth.width, h = s_.depth.height;
    const float max_u = w - 0.5f, max_v = h - 0.5f;
    for (int i = 0; i < n; ++i) {  // the map's pixel and the depth of the point there (-1: outside): vectorised
      const float qx = m_(0, 0) * x[i] + m_(0, 1) * y[i] + m_(0, 2) * z[i] + b_.x();
      const float qy = m_(1, 0) * x[i] + m_(1, 1) * y[i] + m_(1, 2) * z[i] + b_.y();
      const float qz = m_(2, 0) * x[i] + m_(2, 1) * y[i] + m_(2, 2) * z[i] + b_.z();
      const float inv_z = 1.0f / qz;
      const float u = fx_ * qx * inv_z + cx_, v = fy_ * qy * inv_z + cy_;
      const bool inside = (qz > 0.0f) & (u > -0.5f) & (v > -0.5f) & (u < max_u) & (v < max_v);
      const int iu = static_cast<int>(inside ? u + 0.5f : 0.0f), iv = static_cast<int>(inside ? v + 0.5f : 0.0f);
      pixel[i] = inside ? iv * w + iu : -1;  // nearest pixel
      depth[i] = qz - bias_m_;
    }
    const float* map = s_.depth.depth_m.data();
    for (int i = 0; i < n; ++i)  // NaN and +inf in the map (nothing towards the sun): lit
      lit[i] = pixel[i] < 0 || !(map[pixel[i]] < depth[i]) ? 1.0f : 0.0f;
  }

 private:
  const ShadowMap& s_;
  Eigen::Matrix3f m_;
  Eigen::Vector3f b_;
  float fx_, fy_, cx_, cy_, bias_m_;
};

}  // namespace

void shadeDaylight(const RenderedView& view, const SensorPose& pose, const Intrinsics& k, const Daylight& light,
                   const ShadowMap* shadow, const std::vector<float>& texture, ColorImage* rgb) {
  if (rgb->width != view.width || rgb->height != view.height) return;
  const int w = view.width, h = view.height, n_tex = static_cast<int>(texture.size());
  if (view.depth_m.size() != static_cast<size_t>(w) * h || view.geom.size() != view.depth_m.size() ||
      rgb->rgb.size() != 3 * view.depth_m.size())
    return;
  const Eigen::Vector3f sun_cam = (pose.rotation.transpose() * light.toSun()).cast<float>();
  const bool use_shadow = light.sunny && shadow && shadow->valid;
  static const ShadowMap kNoShadow;
  const SunLookup sun_map(use_shadow ? *shadow : kNoShadow, pose, light.shadow_bias_m);
  const Eigen::Matrix3f rot = pose.rotation.cast<float>();
  const NoiseOctave fine(pose.origin, 0.004), coarse(pose.origin, 0.02);
  const float ambient = static_cast<float>(light.ambient), direct = static_cast<float>(light.direct);
  const float exposure = static_cast<float>(light.exposure);
  ShadeRows rows(w);
  rows.ray_x.resize(w);
  for (int u = 0; u < w; ++u) rows.ray_x[u] = static_cast<float>((u - k.cx) / k.fx);
  rows.load(view, k, -1);
  rows.load(view, k, 0);
  for (int v = 0; v < h; ++v) {
    rows.load(view, k, v + 1);
    const int here = ShadeRows::slot(v);
    const int* g = &rows.g[here][1];
    const float *px = &rows.x[here][1], *py = &rows.y[here][1], *pz = &rows.z[here][1];
    int first = 0, last = w - 1;  // the pixels that see something: rows of sky cost nothing
    while (first < w && g[first] < 0) ++first;
    while (last >= first && g[last] < 0) --last;
    if (first > last) continue;
    const int n = last - first + 1;
    lambertRow(rows, ShadeRows::slot(v - 1), here, ShadeRows::slot(v + 1), sun_cam, rows.lambert.data());
    float *dx = rows.dx.data(), *dy = rows.dy.data(), *dz = rows.dz.data();
    for (int u = first; u <= last; ++u) {  // the offset from the camera, world axes
      dx[u] = rot(0, 0) * px[u] + rot(0, 1) * py[u] + rot(0, 2) * pz[u];
      dy[u] = rot(1, 0) * px[u] + rot(1, 1) * py[u] + rot(1, 2) * pz[u];
      dz[u] = rot(2, 0) * px[u] + rot(2, 1) * py[u] + rot(2, 2) * pz[u];
    }
    noiseRow(fine, dx + first, dy + first, dz + first, n, rows.fine.data() + first);
    noiseRow(coarse, dx + first, dy + first, dz + first, n, rows.coarse.data() + first);
    float* lit = rows.lit.data();
    if (use_shadow)
      sun_map.row(px + first, py + first, pz + first, n, rows.sun_pixel.data(), rows.sun_depth.data(), lit + first);
    else
      std::fill(lit + first, lit + last + 1, 1.0f);
    float* gain = rows.gain.data();
    for (int u = first; u <= last; ++u) {
      const int gu = g[u];
      const float amp = gu >= 0 && gu < n_tex ? texture[gu] : 0.0f;
      const float tex = amp > 0.0f ? 1.0f + amp * (0.6f * rows.fine[u] + 0.4f * rows.coarse[u]) : 1.0f;
      const bool seen = gu >= 0 && pz[u] == pz[u];
      gain[u] = seen ? tex * (ambient + lit[u] * direct * rows.lambert[u]) * exposure : 1.0f;  // 1: kept as it is
    }
    uint8_t* out = &rgb->rgb[3 * static_cast<size_t>(v) * w];
    for (int u = first; u <= last; ++u)
      for (int c = 0; c < 3; ++c) {
        const float x = out[3 * u + c] * gain[u];  // rounded to the nearest level, clamped to a byte
        out[3 * u + c] = x > 0.0f ? (x < 254.5f ? static_cast<uint8_t>(x + 0.5f) : 255) : 0;
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
