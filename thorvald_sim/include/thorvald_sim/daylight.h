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

/// renderShadowMap for a camera that moves over a still scene: the map is rendered over a region `margin_m` wider
/// on every side than asked, at the same pixel size (in tiles when it is taller than the renderer's buffer), and
/// kept while it still holds: the same sun and own robot, the asked square within it, and no geom (other than the
/// own robot's) moved by more than 0.5 mm or turned by more than 5 mrad, or shown or hidden, since it was
/// rendered. A kept map gives the same shadows up to its pixel grid: where a shadow edge crosses a pixel the
/// lit/shaded choice of a surface point may differ from a map centred on the asked region.
class ShadowMapCache {
 public:
  explicit ShadowMapCache(double margin_m = 0.5) : margin_m_(margin_m) {}
  /// The map for the square of half side `half_extent_m` around `centre` at `size` pixels across (as
  /// renderShadowMap); `model` is the renderer's.
  const ShadowMap& get(CameraRenderer* renderer, const mjModel* model, const mjData* data, const Daylight& light,
                       const Eigen::Vector3d& centre, double half_extent_m, int size, int own_root_body);
  /// Maps rendered so far (the rest were kept).
  long renders() const { return renders_; }

 private:
  bool holds(const mjModel* model, const mjData* data, const Daylight& light, const Eigen::Vector3d& centre,
             double half_extent_m, int size, int own_root_body) const;
  void remember(const mjModel* model, const mjData* data, int own_root_body);

  double margin_m_;
  ShadowMap map_;
  Daylight light_;
  Eigen::Vector3d centre_ = Eigen::Vector3d::Zero();
  double half_extent_m_ = 0, size_ = 0;
  int own_root_body_ = -1;
  std::vector<double> geoms_;  ///< per geom not of the own robot: position, rotation matrix, alpha
  long renders_ = 0;
};

/// Whether the world point `p` is lit by the sun in `shadow` (true when outside the map).
bool litBySun(const ShadowMap& shadow, const Eigen::Vector3d& p, double bias_m);

/// Shades `rgb` (colorFromView of `view`, same size) in place: each pixel that sees geom g becomes its colour times
/// (1 + texture[g] * noise(world point)) times (ambient + direct * max(0, n . sun) * lit) times exposure, rounded to
/// the nearest level, with noise = 0.6 valueNoise(p, 4 mm) + 0.4 valueNoise(p, 20 mm), n the normal from the depth
/// image's neighbours, lit from `shadow` (nullptr or invalid: lit). `texture` holds one amplitude per geom (0: a
/// uniform, textureless surface). Computed row by row in float (branch-free loops the compiler vectorises): within
/// a level of the same formula in double (but where a point lies within a float's rounding of the shadow's bias).
void shadeDaylight(const RenderedView& view, const SensorPose& pose, const Intrinsics& k, const Daylight& light,
                   const ShadowMap* shadow, const std::vector<float>& texture, ColorImage* rgb);

/// Smooth value noise in [-1, 1] on a 3-D lattice of `cell_m` [m], seeded by the lattice only (deterministic): a
/// lattice point's value is 24 bits of a 32-bit hash of its integer coordinates.
double valueNoise(const Eigen::Vector3d& p, double cell_m);

/// Texture amplitude of a geom of the datasheet cotton row (makeCottonRowWorld) for shadeDaylight, by its name: soil
/// and clods strongly textured, plants less, anything else (a robot's painted or anodised parts) not at all: uniform,
/// so a passive-stereo camera finds no match there.
float cottonGeomTexture(const std::string& geom_name);

}  // namespace thorvald_sim
