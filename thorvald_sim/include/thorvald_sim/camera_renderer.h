#pragma once

#include <mujoco/mujoco.h>

#include <memory>
#include <utility>
#include <stdexcept>
#include <vector>

#include "thorvald_sim/camera_images.h"
#include "thorvald_sim/sensors.h"

namespace thorvald_sim {

/// The renderer could not be created or used (no OpenGL context, an image larger than the model allows).
class RenderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A pinhole view to render: image size, intrinsics (square pixels: fx = fy) and the depth interval the z-buffer
/// covers.
struct CameraView {
  int width = 640, height = 480;
  Intrinsics k = intrinsics(640, 480, 1.2);
  double near_m = 0.05;  ///< [m] nothing closer is seen
  double far_m = 50.0;   ///< [m] nothing farther along the optical axis is seen
};

/// The view a depth camera (with its colour image) needs: its optics, from range_min (or less, for colour) to
/// the farthest range it reports.
CameraView cameraView(const DepthCameraSpec& depth, bool color, double color_range_max_m = 50.0);

/// Rasterises the model's geoms with MuJoCo's OpenGL renderer on the CPU (Mesa's OSMesa/llvmpipe: no display,
/// no GPU): one pass in segmentation mode gives each pixel's geom and the z-buffer its depth. The cost grows with
/// the pixels and the triangles in view, not with pixels times geoms as ray casting every pixel does. llvmpipe
/// splits the image over `LP_NUM_THREADS` threads (default: all cores), read when the first context is created.
///
/// Curved geoms (spheres, capsules, cylinders, ellipsoids) are drawn as MuJoCo tessellates them
/// (`<visual><quality numslices numstacks>`); the pixels that see one get their depth from the pixel's ray
/// against that geom's exact surface, so depth matches the ray caster, and only silhouettes can differ by the
/// tessellation (r (1 - cos(pi / numslices)) for radius r). Planes and boxes are exact up to the 24-bit z-buffer
/// (about z^2 / (near 2^24)). One context per renderer, used from the thread that created it only.
class CameraRenderer {
 public:
  /// Creates the OpenGL context and uploads the model. The model's `<visual><global offwidth offheight>` bound the
  /// images it can render; `<visual><quality offsamples="0">` keeps geom ids exact at edges. Throws RenderError.
  explicit CameraRenderer(const mjModel* model);
  ~CameraRenderer();
  CameraRenderer(const CameraRenderer&) = delete;
  CameraRenderer& operator=(const CameraRenderer&) = delete;

  /// Renders `view` from the optical frame `pose` (z forward, x right, y down) with the model's geoms as they are
  /// in `data`, leaving out the geoms of the robot whose root body is `own_root_body` (-1: none) and invisible
  /// geoms (alpha 0). The read-back pixels are turned into depths and geoms on `threads` threads (llvmpipe's own
  /// threads are set by LP_NUM_THREADS). Throws RenderError for an image larger than the model's offscreen buffer.
  void render(const mjData* data, const SensorPose& pose, const CameraView& view, int own_root_body, RenderedView* out,
              int threads = 1);

  int maxWidth() const;
  int maxHeight() const;
  /// Frames rendered so far.
  unsigned long frames() const { return frames_; }
  /// Geoms of the last frame left out because their bounding spheres lie outside the view frustum.
  int culledGeoms() const { return culled_; }

  /// Where the last frame's CPU time went (this process, every thread) [s].
  struct StageTimes {
    double scene_s = 0;     ///< MuJoCo's scene of the geoms, the own robot and the geoms out of view left out
    double draw_s = 0;      ///< mjr_render: OpenGL calls and llvmpipe's rasterisation
    double readback_s = 0;  ///< glReadPixels of the geom ids and the z-buffer
    double convert_s = 0;   ///< z-buffer to depth, segmentation id to geom, exact depth of curved geoms
  };
  const StageTimes& lastStageTimes() const { return stages_; }

 private:
  /// Throws RenderError for a view that does not fit the offscreen buffer, has no depth range or non-square pixels.
  void checkView(const CameraView& view) const;
  /// MuJoCo's scene of the geoms in `data` without the carrying robot, invisible geoms and geoms out of view;
  /// fills seg_geom_ (segmentation id -> geom) and culled_.
  void keepGeomsInView(const mjData* data, const SensorPose& pose, const CameraView& view, int own_root_body);
  /// Orders the scene's geoms nearest first by their bounding spheres (planes last).
  void sortNearestFirst(const SensorPose& pose);
  /// Reads the drawn ids and depths back; true when read directly as RGBA bytes and 24-bit integers (rgba_,
  /// zbits_), false through MuJoCo (rgb_, zbuf_).
  bool readBack(const CameraView& view);
  /// in_view_ for the curved geoms in the scene.
  void placeCurvedInView(const mjData* data, const SensorPose& pose);
  /// Image rows [row0, row1) of `out` from the read-back buffers, curved geoms with their exact depth.
  void convertRows(int row0, int row1, const mjData* data, const SensorPose& pose, const CameraView& view, bool direct,
                   RenderedView* out) const;
  void refineCurvedDepths(int row, const mjData* data, const SensorPose& pose, const CameraView& view, const int* geom,
                          float* depth) const;

  struct Context;
  const mjModel* m_;
  std::unique_ptr<Context> ctx_;
  std::vector<char> curved_;               ///< per geom: depth refined analytically
  std::vector<int> seg_geom_;              ///< segmentation id -> geom id of the last frame
  std::vector<int> seg_lut_;               ///< segmentation colour (id + 1) -> geom id, -1 for none
  std::vector<unsigned char> rgb_, rgba_;  ///< read back through MuJoCo (rgb_) or directly (rgba_)
  std::vector<float> zbuf_;
  std::vector<uint32_t> zbits_;
  unsigned long frames_ = 0;
  int culled_ = 0;
  StageTimes stages_;
  std::vector<std::pair<double, int>> order_;  ///< geoms drawn nearest first
  std::vector<mjvGeom> sorted_;
  struct CurvedInView;
  std::vector<CurvedInView> in_view_;  ///< per geom: curved geoms drawn in the last frame, in their own frame
};

}  // namespace thorvald_sim
