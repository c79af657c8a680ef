#include "thorvald_sim/camera_images.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

#include "pixel_noise.h"
#include "row_blocks.h"

namespace thorvald_sim {

namespace {

// Each seen geom once per frame (a frame sees few geoms, many pixels each), in the optical frame: for planes and
// boxes the rows of A = R_geom^T R_camera (the faces' normals) and, for boxes, the map from a point in the optical
// frame to the box frame, p_box = A p + b; the other types need their world pose.
enum GeomKind : char { kPlane, kBox, kOther };
struct GeomFrame {
  Eigen::Matrix3d A;
  Eigen::Vector3d b;
  Eigen::Vector3d half;
  Eigen::Matrix3d R;  ///< world frame, for the other types
  Eigen::Vector3d c;
  GeomKind kind = kOther;
};

/// The frames of the geoms `view` sees (indexed by geom id; the others left default).
std::vector<GeomFrame> seenGeomFrames(const RenderedView& view, const mjModel* m, const mjData* d,
                                      const SensorPose& pose) {
  std::vector<GeomFrame> frames(m->ngeom);
  std::vector<char> seen(m->ngeom, 0);
  for (int g : view.geom)
    if (g >= 0) seen[g] = 1;
  for (int g = 0; g < m->ngeom; ++g) {
    if (!seen[g]) continue;
    GeomFrame& f = frames[g];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) f.R(r, c) = d->geom_xmat[9 * g + 3 * r + c];
    f.c = Eigen::Vector3d(d->geom_xpos[3 * g], d->geom_xpos[3 * g + 1], d->geom_xpos[3 * g + 2]);
    f.A = f.R.transpose() * pose.rotation;
    f.b = f.R.transpose() * (pose.origin - f.c);
    f.half = Eigen::Vector3d(m->geom_size[3 * g], m->geom_size[3 * g + 1], m->geom_size[3 * g + 2]);
    const int type = m->geom_type[g];
    f.kind = type == mjGEOM_PLANE ? kPlane : (type == mjGEOM_BOX ? kBox : kOther);
  }
  return frames;
}

/// The depth image's rows from a rendered view of the same size: range, dropout, grazing angle and noise per pixel.
class DepthRows {
 public:
  DepthRows(const RenderedView& view, const RayCaster& caster, const SensorPose& pose, const DepthCameraSpec& s,
            DepthImage* img)
      : view_(view),
        m_(caster.model()),
        pose_(pose),
        width_(s.width),
        k_(intrinsics(s)),
        frames_(seenGeomFrames(view, caster.model(), caster.data(), pose)),
        min_cos_(std::cos(s.grazing_limit_rad)),
        min_cos2_(min_cos_ > 0.0 ? min_cos_ * min_cos_ : 0.0),
        range_min_(static_cast<float>(s.range_min_m)),
        range_max_(static_cast<float>(s.range_max_m)),
        noise_coeff_(s.noise_coeff > 0 ? s.noise_coeff : 0.0),
        // Dropout with probability p: the draw's 24-bit uniform below p 2^24.
        dropout_below_(
            s.dropout > 0 ? static_cast<uint32_t>(std::min(1.0, s.dropout) * (1u << PixelNoise::kUniformBits)) : 0u),
        xs_(s.width),
        xs2_(s.width),
        img_(img) {
    // Per column the ray's x at z = 1 and 1 + x^2 (|ray|^2 without the row's y^2).
    for (int u = 0; u < s.width; ++u) xs_[u] = (u - k_.cx) / k_.fx, xs2_[u] = 1.0 + xs_[u] * xs_[u];
  }

  /// Rows [v0, v1) with the noise stream `noise`.
  void convert(int v0, int v1, PixelNoise& noise) const {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const Eigen::Vector3f none(nan, nan, nan);
    for (int v = v0; v < v1; ++v) {
      const double y = (v - k_.cy) / k_.fy, y2 = y * y;
      const size_t row = static_cast<size_t>(v) * width_;
      const int* geoms = view_.geom.data() + row;
      const float* depths = view_.depth_m.data() + row;
      Eigen::Vector3f* out = img_->points.data() + row;
      // A ray = A (x, y, 1) = x A_0 + (y A_1 + A_2): the second term once per row and geom (neighbouring pixels
      // mostly see the same geom).
      int last = -1;
      const GeomFrame* f = nullptr;
      Eigen::Vector3d row_term;
      for (int u = 0; u < width_; ++u) {
        const int g = geoms[u];
        const float zf = depths[u];
        if (g < 0 || !(zf >= range_min_ && zf <= range_max_)) {
          out[u] = none;
          continue;
        }
        const uint64_t draw = noise.next();
        if (PixelNoise::uniform(draw) < dropout_below_) {
          out[u] = none;
          continue;
        }
        const double z = zf, x = xs_[u];
        if (g != last) {
          last = g;
          f = &frames_[g];
          row_term = f->A.col(1) * y + f->A.col(2);
        }
        if (grazing(*f, row_term, g, u, y, y2, z)) {
          out[u] = none;
          continue;
        }
        const double zn = z + noise_coeff_ * z * z * noise.normal(draw);
        out[u] = Eigen::Vector3f(static_cast<float>(x * zn), static_cast<float>(y * zn), static_cast<float>(zn));
      }
    }
  }

 private:
  /// Seen more obliquely than grazing_limit: the cosine between the ray and the surface normal n is below
  /// min_cos. For planes and boxes, with the face normal n in the optical frame (a row of A):
  /// (n . ray)^2 < min_cos^2 |ray|^2.
  bool grazing(const GeomFrame& f, const Eigen::Vector3d& row_term, int g, int u, double y, double y2, double z) const {
    const double x = xs_[u];
    if (f.kind != kOther) {
      const Eigen::Vector3d a_ray = f.A.col(0) * x + row_term;
      int face = 2;
      if (f.kind == kBox) {  // the face nearest to the point p_box = A (z ray) + b
        const Eigen::Vector3d gap = ((z * a_ray + f.b).cwiseAbs() - f.half).cwiseAbs();
        face = gap[0] <= gap[1] ? (gap[0] <= gap[2] ? 0 : 2) : (gap[1] <= gap[2] ? 1 : 2);
      }
      return a_ray[face] * a_ray[face] < min_cos2_ * (xs2_[u] + y2);
    }
    const Eigen::Vector3d ray(x, y, 1.0);
    const Eigen::Vector3d dir = pose_.rotation * (ray / std::sqrt(xs2_[u] + y2));
    const Eigen::Vector3d nrm =
        geomNormal(m_->geom_type[g], m_->geom_size + 3 * g, f.R, f.c, pose_.origin + pose_.rotation * (ray * z), dir);
    return -nrm.dot(dir) < min_cos_;
  }

  const RenderedView& view_;
  const mjModel* m_;
  const SensorPose& pose_;
  const int width_;
  const Intrinsics k_;
  const std::vector<GeomFrame> frames_;
  const double min_cos_, min_cos2_;
  const float range_min_, range_max_;
  const double noise_coeff_;
  const uint32_t dropout_below_;
  std::vector<double> xs_, xs2_;
  DepthImage* img_;
};

}  // namespace

namespace {

/// Geoms of shiny round steel: spheres, capsules, ellipsoids and cylinders whose name starts with `prefix`.
std::vector<char> shinyGeoms(const mjModel* m, const std::string& prefix) {
  std::vector<char> shiny(m->ngeom, 0);
  if (prefix.empty()) return shiny;
  for (int g = 0; g < m->ngeom; ++g) {
    const int t = m->geom_type[g];
    const char* name = mj_id2name(m, mjOBJ_GEOM, g);
    shiny[g] = (t == mjGEOM_SPHERE || t == mjGEOM_CAPSULE || t == mjGEOM_ELLIPSOID || t == mjGEOM_CYLINDER) && name &&
               std::strncmp(name, prefix.c_str(), prefix.size()) == 0;
  }
  return shiny;
}

/// The true view for the active-stereo model: `exact` (no noise, no dropout; range and grazing applied) as depth
/// and, on shiny geoms, the angle from the glint line (glintAngle: the axis of capsules and cylinders).
DepthTruth depthTruth(const RenderedView& view, const RayCaster& caster, const SensorPose& pose,
                      const DepthCameraSpec& s, const DepthImage& exact) {
  DepthTruth t;
  t.width = s.width, t.height = s.height;
  const size_t n = exact.points.size();
  t.z_m.resize(n);
  t.glint_rad.assign(n, std::numeric_limits<float>::quiet_NaN());
  for (size_t i = 0; i < n; ++i) t.z_m[i] = exact.points[i].z();
  const mjModel* m = caster.model();
  const mjData* d = caster.data();
  const std::vector<char> shiny = shinyGeoms(m, s.stereo.shiny_prefix);
  const Intrinsics k = intrinsics(s);
  for (int v = 0; v < s.height; ++v)
    for (int u = 0; u < s.width; ++u) {
      const size_t i = static_cast<size_t>(v) * s.width + u;
      const int g = view.geom[i];
      if (g < 0 || !shiny[g] || !(t.z_m[i] > 0.0f)) continue;
      const Eigen::Vector3d ray((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
      const Eigen::Vector3d dir = pose.rotation * ray.normalized();
      const Eigen::Vector3d point = pose.origin + pose.rotation * (ray * t.z_m[i]);
      const Eigen::Vector3d nrm = caster.normal(g, point, dir);
      const mjtNum* xmat = d->geom_xmat + 9 * g;  // row-major: the geom's z axis is the third column
      const bool round = m->geom_type[g] == mjGEOM_CAPSULE || m->geom_type[g] == mjGEOM_CYLINDER;
      const Eigen::Vector3d axis = round ? Eigen::Vector3d(xmat[2], xmat[5], xmat[8]) : Eigen::Vector3d::Zero();
      const Eigen::Vector3d centre(d->geom_xpos[3 * g], d->geom_xpos[3 * g + 1], d->geom_xpos[3 * g + 2]);
      t.glint_rad[i] = static_cast<float>(glintAngle(nrm, point, centre, axis, pose.origin));
    }
  return t;
}

}  // namespace

void depthFromView(const RenderedView& view, const RayCaster& caster, const SensorPose& pose, const DepthCameraSpec& s,
                   std::mt19937& rng, DepthImage* img, int threads) {
  if (s.realism == Realism::kDatasheet && view.width == s.width && view.height == s.height) {
    DepthCameraSpec exact = s;
    exact.realism = Realism::kIdeal, exact.noise_coeff = 0.0, exact.dropout = 0.0;
    depthFromView(view, caster, pose, exact, rng, img, threads);
    const std::vector<float> z =
        applyActiveStereo(depthTruth(view, caster, pose, s, *img), intrinsics(s).fx, s.stereo, rng);
    const Intrinsics k = intrinsics(s);
    for (int v = 0; v < s.height; ++v)
      for (int u = 0; u < s.width; ++u) {
        const size_t i = static_cast<size_t>(v) * s.width + u;
        img->points[i] = (Eigen::Vector3d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0) * z[i]).cast<float>();
      }
    return;
  }
  img->width = s.width;
  img->height = s.height;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const size_t n = static_cast<size_t>(s.width) * s.height;
  if (view.width != s.width || view.height != s.height) {
    img->points.assign(n, Eigen::Vector3f(nan, nan, nan));
    return;
  }
  img->points.resize(n);  // every pixel is written below
  const DepthRows rows(view, caster, pose, s, img);
  // Rows in a fixed number of blocks, each with its own noise stream drawn in order from `rng`: the image is the
  // same whatever the number of threads.
  constexpr int kBlocks = 8;
  std::vector<PixelNoise> noises;
  for (int b = 0; b < kBlocks; ++b) noises.emplace_back(rng);
  forBlocks(kBlocks, threads, [&](int b) {
    PixelNoise noise = noises[b];  // a copy on this thread's stack: the streams share cache lines in the vector
    rows.convert(s.height * b / kBlocks, s.height * (b + 1) / kBlocks, noise);
  });
}

DepthImage depthFromView(const RenderedView& view, const RayCaster& caster, const SensorPose& pose,
                         const DepthCameraSpec& spec, std::mt19937& rng) {
  DepthImage img;
  depthFromView(view, caster, pose, spec, rng, &img);
  return img;
}

ColorImage colorFromView(const RenderedView& view, const mjModel* model, const ColorCameraSpec& spec) {
  ColorImage img;
  colorFromView(view, model, spec, &img);
  return img;
}

void colorFromView(const RenderedView& view, const mjModel* model, const ColorCameraSpec& s, ColorImage* img) {
  const Intrinsics k = intrinsics(s);
  img->width = s.width;
  img->height = s.height;
  img->rgb.resize(static_cast<size_t>(s.width) * s.height * 3);
  const bool same = view.width == s.width && view.height == s.height;
  std::vector<std::array<uint8_t, 3>> palette(model->ngeom);
  for (int g = 0; g < model->ngeom; ++g)
    for (int c = 0; c < 3; ++c) palette[g][c] = static_cast<uint8_t>(std::lround(255.0 * model->geom_rgba[4 * g + c]));
  const double range2 = s.range_max_m * s.range_max_m;
  std::vector<double> column(s.width);  // 1 + x^2 of each column's ray (x, y, 1)
  for (int u = 0; u < s.width; ++u) {
    const double x = (u - k.cx) / k.fx;
    column[u] = 1.0 + x * x;
  }
  for (int v = 0; v < s.height; ++v) {
    const double y = (v - k.cy) / k.fy;
    for (int u = 0; u < s.width; ++u) {
      const size_t i = static_cast<size_t>(v) * s.width + u;
      const int g = same ? view.geom[i] : -1;
      bool hit = g >= 0;
      if (hit) {  // the colour camera's range is along the ray, the z-buffer's along the axis
        const double z = view.depth_m[i];
        hit = z * z * (column[u] + y * y) <= range2;
      }
      const uint8_t* from = hit ? palette[g].data() : s.background;
      uint8_t* px = &img->rgb[3 * i];
      px[0] = from[0], px[1] = from[1], px[2] = from[2];
    }
  }
}

}  // namespace thorvald_sim
