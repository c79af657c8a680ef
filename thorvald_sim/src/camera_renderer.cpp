#include "thorvald_sim/camera_renderer.h"

#include <GL/osmesa.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <ctime>

#include "curved_depth.h"
#include "row_blocks.h"

namespace thorvald_sim {

namespace {

/// CPU time of this process, every thread [s].
double cpuSeconds() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/// A perspective z-buffer's value back to the distance along the optical axis. With the window depth d = k / K in
/// [0, 1] (k the buffer's integer, K = 2^24 - 1 its largest value): z = near far / (far - d (far - near))
/// = near far / (near + (K - k) (far - near) / K). The second form takes K - k exactly (no cancellation near the far
/// plane, where d is within a float's rounding of 1).
struct ZBufferToDepth {
  static constexpr uint32_t kMax = (1u << 24) - 1;
  float nf, near, step;
  ZBufferToDepth(double near_m, double far_m)
      : nf(static_cast<float>(near_m * far_m)),
        near(static_cast<float>(near_m)),
        step(static_cast<float>((far_m - near_m) / kMax)) {}
  /// `k` of a 24-bit buffer; +inf for the far plane (nothing drawn).
  float depth(uint32_t k) const {
    return k >= kMax ? std::numeric_limits<float>::infinity() : nf / (near + static_cast<float>(kMax - k) * step);
  }
  /// A window depth in [0, 1] as MuJoCo's mjr_readPixels gives it.
  float depthOfFraction(float d) const {
    return d >= 1.0f ? std::numeric_limits<float>::infinity() : nf / (near + (1.0f - d) * (step * kMax));
  }
};

/// One image row of the read-back buffers (bottom-up in OpenGL, given here already as the image's row): RGBA bytes
/// whose red, green and blue hold the segmentation id + 1, and the z-buffer as 32-bit integers (the 24-bit depth in
/// the high bits). Writes each pixel's geom (-1: none) and depth (+inf: none).
void convertRow(const unsigned char* rgba, const uint32_t* zbits, int width, const int* lut, int lut_size,
                ZBufferToDepth to_depth, int* geom, float* depth) {
  for (int u = 0; u < width; ++u) {
    const unsigned char* c = rgba + 4 * u;
    const int id = c[0] | (c[1] << 8) | (c[2] << 16);
    const int g = id < lut_size ? lut[id] : -1;
    const float z = to_depth.depth(zbits[u] >> 8);
    const bool seen = g >= 0 && z < std::numeric_limits<float>::infinity();
    geom[u] = seen ? g : -1;
    depth[u] = seen ? z : std::numeric_limits<float>::infinity();
  }
}

/// The same from MuJoCo's mjr_readPixels: RGB bytes and the window depth as floats in [0, 1].
void convertRowFloat(const unsigned char* rgb, const float* zbuf, int width, const int* lut, int lut_size,
                     ZBufferToDepth to_depth, int* geom, float* depth) {
  for (int u = 0; u < width; ++u) {
    const unsigned char* c = rgb + 3 * u;
    const int id = c[0] | (c[1] << 8) | (c[2] << 16);
    const int g = id < lut_size ? lut[id] : -1;
    const float z = to_depth.depthOfFraction(zbuf[u]);
    const bool seen = g >= 0 && z < std::numeric_limits<float>::infinity();
    geom[u] = seen ? g : -1;
    depth[u] = seen ? z : std::numeric_limits<float>::infinity();
  }
}

/// The view frustum in the optical frame, as planes through the origin (unit normals pointing out of the view) and
/// the near/far planes; a geom whose bounding sphere lies wholly outside one of them is not drawn.
class ViewFrustum {
 public:
  ViewFrustum(const mjModel* m, const mjData* data, const SensorPose& pose, const CameraView& view)
      : m_(m), data_(data), pose_(pose), near_m_(view.near_m), far_m_(view.far_m) {
    const Intrinsics& k = view.k;
    const double x_min = (-0.5 - k.cx) / k.fx, x_max = (view.width - 0.5 - k.cx) / k.fx;
    const double y_min = (-0.5 - k.cy) / k.fy, y_max = (view.height - 0.5 - k.cy) / k.fy;
    side_[0] = Eigen::Vector3d(1.0, 0.0, -x_max).normalized();
    side_[1] = Eigen::Vector3d(-1.0, 0.0, x_min).normalized();
    side_[2] = Eigen::Vector3d(0.0, 1.0, -y_max).normalized();
    side_[3] = Eigen::Vector3d(0.0, -1.0, y_min).normalized();
  }
  bool outside(int geom) const {
    const double r = m_->geom_rbound[geom];
    if (!(r > 0.0)) return false;  // planes (and anything without a bound) are always drawn
    const Eigen::Vector3d c =
        pose_.rotation.transpose() *
        (Eigen::Vector3d(data_->geom_xpos[3 * geom], data_->geom_xpos[3 * geom + 1], data_->geom_xpos[3 * geom + 2]) -
         pose_.origin);
    if (c.z() + r < near_m_ || c.z() - r > far_m_) return true;
    for (const auto& n : side_)
      if (n.dot(c) > r) return true;
    return false;
  }

 private:
  const mjModel* m_;
  const mjData* data_;
  const SensorPose& pose_;
  double near_m_, far_m_;
  Eigen::Vector3d side_[4];
};

/// MuJoCo's camera for the optical frame `pose` (z forward, y down, so OpenGL's up is -y and its right x) and the
/// view's intrinsics.
mjvGLCamera glCamera(const SensorPose& pose, const CameraView& view) {
  const Intrinsics& k = view.k;
  mjvGLCamera cam;
  for (int i = 0; i < 3; ++i) {
    cam.pos[i] = static_cast<float>(pose.origin[i]);
    cam.forward[i] = static_cast<float>(pose.rotation(i, 2));
    cam.up[i] = static_cast<float>(-pose.rotation(i, 1));
  }
  cam.frustum_near = static_cast<float>(view.near_m);
  cam.frustum_far = static_cast<float>(view.far_m);
  // Pixel u spans [u - 0.5, u + 0.5] and sees x / z = (u - cx) / f; OpenGL's y is up, the image's v down. MuJoCo
  // sets the frustum's width from its height and the viewport's aspect, so fx must equal fy.
  cam.frustum_center = static_cast<float>(view.near_m * (0.5 * (view.width - 1) - k.cx) / k.fx);
  cam.frustum_top = static_cast<float>(view.near_m * (k.cy + 0.5) / k.fy);
  cam.frustum_bottom = static_cast<float>(-view.near_m * (view.height - 0.5 - k.cy) / k.fy);
  return cam;
}

}  // namespace

/// A curved geom seen from a camera, in the geom's frame: the camera's origin `o` and A = R_geom^T R_camera, which
/// turns a ray (x, y, 1) of the optical frame into the geom frame.
struct CameraRenderer::CurvedInView {
  Eigen::Matrix3d A;
  Eigen::Vector3d o;
  int type = -1;
  double size[3] = {0, 0, 0};
};

struct CameraRenderer::Context {
  OSMesaContext gl = nullptr;
  std::vector<unsigned char> window;  ///< the default framebuffer OSMesa needs; MuJoCo draws offscreen
  mjrContext con;
  mjvScene scene;
  mjvOption option;
  mjvPerturb perturb;
  bool have_con = false, have_scene = false;
  /// OSMesa's own glReadPixels (the process may also link a GL library whose entry points go elsewhere).
  using ReadPixels = void (*)(GLint, GLint, GLsizei, GLsizei, GLenum, GLenum, void*);
  ReadPixels read_pixels = nullptr;
  using Finish = void (*)();
  Finish finish = nullptr;

  void makeCurrent() const {
    if (!OSMesaMakeCurrent(gl, const_cast<unsigned char*>(window.data()), GL_UNSIGNED_BYTE, 16, 16))
      throw RenderError("OSMesaMakeCurrent failed");
  }
};

CameraRenderer::CameraRenderer(const mjModel* model) : m_(model), ctx_(std::make_unique<Context>()) {
  ctx_->gl = OSMesaCreateContextExt(OSMESA_RGBA, 24, 8, 0, nullptr);
  if (!ctx_->gl) throw RenderError("cannot create an OSMesa OpenGL context (libosmesa6)");
  ctx_->window.resize(16 * 16 * 4);
  ctx_->makeCurrent();
  mjr_defaultContext(&ctx_->con);
  mjr_makeContext(m_, &ctx_->con, mjFONTSCALE_50);
  ctx_->have_con = true;
  mjr_setBuffer(mjFB_OFFSCREEN, &ctx_->con);
  ctx_->read_pixels = reinterpret_cast<Context::ReadPixels>(OSMesaGetProcAddress("glReadPixels"));
  ctx_->finish = reinterpret_cast<Context::Finish>(OSMesaGetProcAddress("glFinish"));
  if (ctx_->con.currentBuffer != mjFB_OFFSCREEN) throw RenderError("MuJoCo has no offscreen buffer in this context");
  curved_.resize(m_->ngeom);
  for (int g = 0; g < m_->ngeom; ++g) {
    const int t = m_->geom_type[g];
    curved_[g] = t == mjGEOM_SPHERE || t == mjGEOM_CAPSULE || t == mjGEOM_CYLINDER || t == mjGEOM_ELLIPSOID;
  }
  mjv_defaultScene(&ctx_->scene);
  mjv_makeScene(m_, &ctx_->scene, m_->ngeom + 100);
  ctx_->have_scene = true;
  mjv_defaultOption(&ctx_->option);
  for (int g = 0; g < mjNGROUP; ++g) ctx_->option.geomgroup[g] = 1;  // the ray caster ignores groups too
  mjv_defaultPerturb(&ctx_->perturb);
  mjvScene& s = ctx_->scene;
  for (int f = 0; f < mjNRNDFLAG; ++f) s.flags[f] = 0;
  s.flags[mjRND_SEGMENT] = 1;
  s.flags[mjRND_IDCOLOR] = 1;
  s.flags[mjRND_CULL_FACE] = 1;
  s.stereo = mjSTEREO_NONE;
}

CameraRenderer::~CameraRenderer() {
  if (ctx_->gl) OSMesaMakeCurrent(ctx_->gl, ctx_->window.data(), GL_UNSIGNED_BYTE, 16, 16);
  if (ctx_->have_scene) mjv_freeScene(&ctx_->scene);
  if (ctx_->have_con) mjr_freeContext(&ctx_->con);
  if (ctx_->gl) OSMesaDestroyContext(ctx_->gl);
}

int CameraRenderer::maxWidth() const { return ctx_->con.offWidth; }
int CameraRenderer::maxHeight() const { return ctx_->con.offHeight; }

void CameraRenderer::render(const mjData* data, const SensorPose& pose, const CameraView& view, int own_root_body,
                            RenderedView* out, int threads) {
  checkView(view);
  const double t_start = cpuSeconds();
  ctx_->makeCurrent();
  mjvScene& s = ctx_->scene;
  keepGeomsInView(data, pose, view, own_root_body);
  sortNearestFirst(pose);
  s.nlight = 0;
  const mjvGLCamera cam = glCamera(pose, view);
  s.camera[0] = cam;
  s.camera[1] = cam;
  const mjrRect rect = {0, 0, view.width, view.height};
  const double t_scene = cpuSeconds();
  mjr_render(rect, &s, &ctx_->con);
  // llvmpipe rasterises when the frame is flushed: finish here so that the draw's time includes it.
  if (ctx_->finish) ctx_->finish();
  const double t_draw = cpuSeconds();
  const bool direct = readBack(view);
  const double t_read = cpuSeconds();
  ++frames_;

  const size_t n = static_cast<size_t>(view.width) * view.height;
  out->width = view.width;
  out->height = view.height;
  out->depth_m.resize(n);
  out->geom.resize(n);
  // Segmentation colour (id + 1, 0 for the background) -> geom, -1 where none: one lookup per pixel, no range test.
  seg_lut_.assign(seg_geom_.size() + 1, -1);
  std::copy(seg_geom_.begin(), seg_geom_.end(), seg_lut_.begin() + 1);
  placeCurvedInView(data, pose);
  // The pixels that see a curved geom cost a ray test each: the rows go in blocks over the threads.
  constexpr int kBlocks = 8;
  forBlocks(kBlocks, threads, [&](int b) {
    convertRows(view.height * b / kBlocks, view.height * (b + 1) / kBlocks, data, pose, view, direct, out);
  });
  const double t_convert = cpuSeconds();
  stages_.scene_s = t_scene - t_start;
  stages_.draw_s = t_draw - t_scene;
  stages_.readback_s = t_read - t_draw;
  stages_.convert_s = t_convert - t_read;
}

void CameraRenderer::checkView(const CameraView& view) const {
  if (view.width < 1 || view.height < 1 || view.width > maxWidth() || view.height > maxHeight())
    throw RenderError("image " + std::to_string(view.width) + "x" + std::to_string(view.height) +
                      " does not fit the model's offscreen buffer " + std::to_string(maxWidth()) + "x" +
                      std::to_string(maxHeight()) + " (<visual><global offwidth offheight>)");
  if (!(view.near_m > 0.0 && view.far_m > view.near_m)) throw RenderError("camera view needs 0 < near < far");
  if (!(view.k.fx > 0.0) || std::fabs(view.k.fx - view.k.fy) > 1e-9 * view.k.fx)
    throw RenderError("camera view needs square pixels (fx = fy > 0)");
}

void CameraRenderer::keepGeomsInView(const mjData* data, const SensorPose& pose, const CameraView& view,
                                     int own_root_body) {
  mjvScene& s = ctx_->scene;
  s.ngeom = 0;
  // mjv_addGeoms only reads the state; its signature is not const.
  mjv_addGeoms(m_, const_cast<mjData*>(data), &ctx_->option, &ctx_->perturb, mjCAT_STATIC | mjCAT_DYNAMIC, &s);
  const ViewFrustum frustum(m_, data, pose, view);
  // Leave out the carrying robot, invisible geoms and geoms out of view; remember which geom each segmentation id
  // stands for.
  seg_geom_.assign(s.ngeom, -1);
  int kept = 0;
  culled_ = 0;
  for (int i = 0; i < s.ngeom; ++i) {
    const mjvGeom& g = s.geoms[i];
    if (g.objtype != mjOBJ_GEOM || g.objid < 0) continue;
    if (own_root_body >= 0 && m_->body_rootid[m_->geom_bodyid[g.objid]] == own_root_body) continue;
    if (m_->geom_rgba[4 * g.objid + 3] == 0.0f) continue;
    if (frustum.outside(g.objid)) {
      ++culled_;
      continue;
    }
    if (g.segid >= 0 && g.segid < static_cast<int>(seg_geom_.size())) seg_geom_[g.segid] = g.objid;
    s.geoms[kept++] = g;
  }
  s.ngeom = kept;
}

void CameraRenderer::sortNearestFirst(const SensorPose& pose) {
  // Nearest first: the z-buffer then rejects the hidden parts of the geoms drawn later before they are written.
  mjvScene& s = ctx_->scene;
  const int kept = s.ngeom;
  order_.clear();
  for (int i = 0; i < kept; ++i) {
    const mjvGeom& g = s.geoms[i];
    const double r = m_->geom_rbound[g.objid];
    const Eigen::Vector3d c(g.pos[0] - pose.origin.x(), g.pos[1] - pose.origin.y(), g.pos[2] - pose.origin.z());
    order_.emplace_back(r > 0.0 ? std::max(0.0, c.dot(pose.rotation.col(2)) - r) : 1e30, i);
  }
  std::sort(order_.begin(), order_.end());
  sorted_.resize(kept);
  for (int i = 0; i < kept; ++i) sorted_[i] = s.geoms[order_[i].second];
  std::copy(sorted_.begin(), sorted_.end(), s.geoms);
}

bool CameraRenderer::readBack(const CameraView& view) {
  const size_t n = static_cast<size_t>(view.width) * view.height;
  const mjrRect rect = {0, 0, view.width, view.height};
  const bool direct = ctx_->read_pixels && ctx_->con.offSamples == 0;
  if (direct) {
    // The offscreen buffer is bound for reading (mjr_setBuffer) and needs no resolve: read it in its own formats,
    // RGBA bytes and 24-bit depth as unsigned integers, which Mesa copies without converting each pixel.
    rgba_.resize(4 * n);
    zbits_.resize(n);
    ctx_->read_pixels(0, 0, view.width, view.height, GL_RGBA, GL_UNSIGNED_BYTE, rgba_.data());
    ctx_->read_pixels(0, 0, view.width, view.height, GL_DEPTH_COMPONENT, GL_UNSIGNED_INT, zbits_.data());
  } else {
    rgb_.resize(3 * n);
    zbuf_.resize(n);
    mjr_readPixels(rgb_.data(), zbuf_.data(), rect, &ctx_->con);
  }
  return direct;
}

void CameraRenderer::placeCurvedInView(const mjData* data, const SensorPose& pose) {
  // The curved geoms drawn, each in its own frame once per frame (their pixels' exact depths below).
  const mjvScene& s = ctx_->scene;
  in_view_.resize(m_->ngeom);
  for (int i = 0; i < s.ngeom; ++i) {
    const int g = s.geoms[i].objid;
    if (!curved_[g]) continue;
    Eigen::Matrix3d R;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) R(r, c) = data->geom_xmat[9 * g + 3 * r + c];
    CurvedInView& c = in_view_[g];
    c.A = R.transpose() * pose.rotation;
    c.o = R.transpose() * (pose.origin - Eigen::Vector3d(data->geom_xpos[3 * g], data->geom_xpos[3 * g + 1],
                                                         data->geom_xpos[3 * g + 2]));
    c.type = m_->geom_type[g];
    for (int k = 0; k < 3; ++k) c.size[k] = m_->geom_size[3 * g + k];
  }
}

void CameraRenderer::convertRows(int row0, int row1, const mjData* data, const SensorPose& pose, const CameraView& view,
                                 bool direct, RenderedView* out) const {
  const ZBufferToDepth to_depth(view.near_m, view.far_m);
  const int lut_size = static_cast<int>(seg_lut_.size());
  for (int row = row0; row < row1; ++row) {
    const size_t src = static_cast<size_t>(view.height - 1 - row) * view.width;  // OpenGL: bottom row first
    const size_t dst = static_cast<size_t>(row) * view.width;
    float* depth = &out->depth_m[dst];
    int* geom = &out->geom[dst];
    if (direct)
      convertRow(&rgba_[4 * src], &zbits_[src], view.width, seg_lut_.data(), lut_size, to_depth, geom, depth);
    else
      convertRowFloat(&rgb_[3 * src], &zbuf_[src], view.width, seg_lut_.data(), lut_size, to_depth, geom, depth);
    refineCurvedDepths(row, data, pose, view, geom, depth);
  }
}

void CameraRenderer::refineCurvedDepths(int row, const mjData* data, const SensorPose& pose, const CameraView& view,
                                        const int* geom, float* depth) const {
  // Tessellation only decided which geom a pixel sees; the depth of a curved geom comes from its exact surface.
  const double y = (row - view.k.cy) / view.k.fy;
  const mjtNum pnt[3] = {pose.origin.x(), pose.origin.y(), pose.origin.z()};
  int last = -1;
  Eigen::Vector3d row_term;  // A (0, y, 1) of the last geom
  for (int u = 0; u < view.width; ++u) {
    const int g = geom[u];
    if (g < 0 || !curved_[g]) continue;
    const CurvedInView& c = in_view_[g];
    if (g != last) last = g, row_term = c.A.col(1) * y + c.A.col(2);
    const double x = (u - view.k.cx) / view.k.fx;
    double z = curvedDepth(c.type, c.size, c.o, c.A.col(0) * x + row_term);
    if (z == -2.0) {  // MuJoCo's intersection, along the unit ray
      const Eigen::Vector3d ray(x, y, 1.0);
      const double len = ray.norm();
      const Eigen::Vector3d dir = pose.rotation * (ray / len);
      const mjtNum vec[3] = {dir.x(), dir.y(), dir.z()};
      const double t = mju_rayGeom(data->geom_xpos + 3 * g, data->geom_xmat + 9 * g, m_->geom_size + 3 * g, pnt, vec,
                                   m_->geom_type[g]);
      z = t >= 0.0 ? t / len : -1.0;
    }
    if (z >= 0.0) depth[u] = static_cast<float>(z);
  }
}

CameraView cameraView(const DepthCameraSpec& depth, bool color, double color_range_max_m) {
  CameraView v;
  v.width = depth.width;
  v.height = depth.height;
  v.k = intrinsics(depth);
  // The near plane sets the z-buffer's resolution (about z^2 / (near 2^24)): as far out as the images allow.
  v.near_m = std::max(0.01, color ? std::min(depth.range_min_m, 0.1) : depth.range_min_m);
  v.far_m = std::max(v.near_m * 2.0, 1.001 * std::max(depth.range_max_m, color ? color_range_max_m : 0.0));
  return v;
}

}  // namespace thorvald_sim
