#pragma once

// A camera's images from one rendered view: the active-stereo depth image and the flat-colour image.

#include <mujoco/mujoco.h>

#include <random>
#include <vector>

#include "thorvald_sim/ray_caster.h"
#include "thorvald_sim/sensors.h"

namespace thorvald_sim {

/// What a camera sees, per pixel (row-major, row 0 at the top): the depth along the optical axis and the geom.
struct RenderedView {
  int width = 0, height = 0;
  std::vector<float> depth_m;  ///< z in the optical frame [m]; +inf where no geom is seen
  std::vector<int> geom;       ///< geom id, -1 where none
};

/// Depth image of an active-stereo camera (noise growing with z^2, dropouts, no depth at grazing angles) from a
/// rendered view of the same size and optics; `caster` gives the surface normals of the geoms seen (it needs no
/// prepare). Same outputs as simulateDepth on the same geometry. With spec.realism datasheet: the exact depth (range
/// and grazing limits only) through applyActiveStereo, shiny geoms by spec.stereo.shiny_prefix.
DepthImage depthFromView(const RenderedView& view, const RayCaster& caster, const SensorPose& pose,
                         const DepthCameraSpec& spec, std::mt19937& rng);
/// The same into `out`, reusing its memory (a camera's frames are the same size every time), with the rows split
/// over `threads` threads. The per-pixel noise comes from fast generators seeded from `rng`, one per fixed block of
/// rows, so the image does not depend on the number of threads.
void depthFromView(const RenderedView& view, const RayCaster& caster, const SensorPose& pose,
                   const DepthCameraSpec& spec, std::mt19937& rng, DepthImage* out, int threads = 1);

/// Colour image (each pixel the colour of its geom, the background beyond `range_max_m` or where nothing is seen)
/// from a rendered view of the same size and optics.
ColorImage colorFromView(const RenderedView& view, const mjModel* model, const ColorCameraSpec& spec);
void colorFromView(const RenderedView& view, const mjModel* model, const ColorCameraSpec& spec, ColorImage* out);

}  // namespace thorvald_sim
