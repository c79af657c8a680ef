#pragma once

// Daylight on a rendered colour image (the `datasheet` cameras of outdoor worlds): the sun's direction, hard shadows
// from a depth view rendered from the sun (a shadow map: a pixel is lit when nothing lies between its surface point
// and the sun), overcast light (mostly ambient, no hard shadows), Lambert shading from the surface normals of the
// depth image, a surface texture (value noise on the world position, so it stays on the surface as the camera
// moves) and the exposure. The colour image without it is each geom's flat colour (colorFromView).

#include <Eigen/Core>
#include <random>
#include <string>
#include <vector>

#include "thorvald_sim/camera_renderer.h"

namespace thorvald_sim {

struct Daylight {
  bool sunny = true;               ///< false: overcast
  double sun_elevation_rad = 0.9;  ///< above the horizon
  double sun_azimuth_rad = 0.6;    ///< from world +x towards +y
  double ambient = 0.35;           ///< sky light on every surface (overcast: most of the light)
  double direct = 0.85;            ///< sunlight on a surface facing the sun (overcast: the diffuse sun's share)
  double exposure = 1.0;           ///< gain on the shaded colour; above 255 a channel saturates
  double shadow_bias_m = 0.012;    ///< a surface this near the sun's depth counts as lit
  /// Unit vector from a surface towards the sun (world).
  Eigen::Vector3d toSun() const;
};

/// Sunny light with the sun at the given elevation and azimuth [rad].
Daylight sunnyDaylight(double elevation_rad, double azimuth_rad);
/// Overcast light: ambient 0.9, direct 0.1, the sun's direction kept for the soft share.
Daylight overcastDaylight(double elevation_rad, double azimuth_rad);
/// One draw of the day: sunny (60 %) or overcast, sun elevation 30..70 deg, azimuth anywhere, exposure 0.9..1.1.
Daylight randomDaylight(std::mt19937& rng);

/// The sun's view of a region: a depth image rendered from far along toSun() looking down it.
struct ShadowMap {
  SensorPose pose;
  CameraView view;
  RenderedView depth;
  bool valid = false;
};

/// Renders the sun's view of the square of half side `half_extent_m` around `centre` (world), at `size` x `size`
/// pixels (within the renderer's offscreen buffer), leaving out the body tree of `own_root_body` (-1: none). Throws
/// RenderError like CameraRenderer::render. No shadow map (valid false) for an overcast day.
ShadowMap renderShadowMap(CameraRenderer* renderer, const mjData* data, const Daylight& light,
                          const Eigen::Vector3d& centre, double half_extent_m, int size, int own_root_body);

/// Whether the world point `p` is lit by the sun in `shadow` (true when outside the map).
bool litBySun(const ShadowMap& shadow, const Eigen::Vector3d& p, double bias_m);

/// Shades `rgb` (colorFromView of `view`, same size) in place: each pixel that sees geom g becomes its colour times
/// (1 + texture[g] * noise(world point)) times (ambient + direct * max(0, n . sun) * lit) times exposure, n the
/// normal from the depth image's neighbours, lit from `shadow` (nullptr or invalid: lit). `texture` holds one
/// amplitude per geom (0: a uniform, textureless surface).
void shadeDaylight(const RenderedView& view, const SensorPose& pose, const Intrinsics& k, const Daylight& light,
                   const ShadowMap* shadow, const std::vector<float>& texture, ColorImage* rgb);

/// Smooth value noise in [-1, 1] on a 3-D lattice of `cell_m` [m], seeded by the lattice only (deterministic).
double valueNoise(const Eigen::Vector3d& p, double cell_m);

/// Texture amplitude of a geom of the datasheet cotton row (makeCottonRowWorld) for shadeDaylight, by its name: soil
/// and clods strongly textured, plants less, anything else (a robot's painted or anodised parts) not at all: uniform,
/// so a passive-stereo camera finds no match there.
float cottonGeomTexture(const std::string& geom_name);

}  // namespace thorvald_sim
