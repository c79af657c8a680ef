#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "cotton_harvester/perception/camera_model.h"

namespace cotton_harvester {
namespace perception {

/// Light of a synthetic scene.
enum class Lighting {
  kSunny,   ///< strong directional sun with cast shadows and leaf glints
  kCloudy,  ///< diffuse, slightly blue, no shadows
  kShade,   ///< the row in the shadow of a building or tree line: dim, diffuse and blue
};

std::optional<Lighting> parseLighting(const std::string& name);
std::string toString(Lighting lighting);

/// What a synthetic view of a cotton row from the rover's downward camera holds. Lengths in metres in the camera
/// frame (x right across the row, y down the image = along the row, z down towards the ground).
struct SceneParams {
  CameraIntrinsics intrinsics;
  Lighting lighting = Lighting::kSunny;
  double camera_height_m = 2.20;       ///< camera above the ground (paper §2.1) [m]
  int plants_min = 2, plants_max = 4;  ///< plants in view [-]
  double plant_spacing_m = 0.30;       ///< along the row (paper §2.13) [m]
  double row_offset_max_m = 0.35;      ///< |x| of the row line [m]
  int bolls_per_plant_min = 3, bolls_per_plant_max = 5;
  double boll_radius_min_m = 0.025, boll_radius_max_m = 0.040;
  double boll_height_min_m = 0.20, boll_height_max_m = 1.05;  ///< boll centre above ground [m]
  double canopy_radius_m = 0.40;                              ///< horizontal spread of a plant [m]
  int leaves_per_plant = 22;
  double end_effector_probability = 1.0;  ///< chance that the end-effector is in view [0, 1]
  double depth_noise_per_m2 = 0.002;      ///< stereo depth noise sigma = k z^2 [1/m]
  double hole_fraction = 0.01;            ///< share of single pixels without depth [0, 1]
  int hole_blobs = 4;                     ///< larger patches without depth [-]
  int invalid_left_columns = 24;          ///< left image border the stereo matcher cannot fill [px]
  double pixel_noise = 3.0;               ///< image noise sigma [grey levels]
  /// Auto-exposure and white balance vary from frame to frame: a gain drawn in [min, max] and a per-channel
  /// tint within +-white_balance_jitter [-].
  double exposure_min = 0.75, exposure_max = 1.2;
  double white_balance_jitter = 0.06;
  /// Sunny frames: the end-effector's glossy housing reflects the sky, mixing its colour with white by up to
  /// this share (its blue channel rises well above the paper's B <= 60) [0, 1].
  double end_effector_sheen_max = 0.35;
  /// Chance that a boll grows touching the previous boll of its plant (a cluster the segmenter must split) [0, 1].
  double touching_probability = 0.3;
  /// Chance that a leaf lies just above a boll, hiding part of it [0, 1].
  double leaf_over_boll_probability = 0.3;
  /// White and bright things that are not bolls, this many in view: plant labels on stakes, plastic bags caught in
  /// the plants, pieces of aluminium, large white stones (kClutter). 0: none, and the rest of the scene is drawn
  /// exactly as without the option [-].
  int clutter_items = 0;
};

/// A shape of the scene. Planar shapes are horizontal (facing the camera) at depth centre.z.
struct ScenePrimitive {
  enum class Shape { kEllipse, kRectangle, kSphere };
  enum class Kind { kLeaf, kStem, kBoll, kArm, kPost, kEndEffector, kGlint, kStone, kClutter };
  Shape shape = Shape::kEllipse;
  Kind kind = Kind::kLeaf;
  cv::Point3d centre;                  ///< [m]
  double a = 0.0, b = 0.0;             ///< semi-axes (ellipse) or half length / half width (rectangle) [m]
  double angle_rad = 0.0;              ///< orientation of the a axis from +x [rad]
  double radius = 0.0;                 ///< sphere radius [m]
  cv::Vec3f albedo{0.5f, 0.5f, 0.5f};  ///< BGR reflectance [0, 1]
  int boll_index = -1;                 ///< index into SceneLayout::bolls for kBoll
};

/// The true state of one boll.
struct TrueBoll {
  cv::Point3d centre;  ///< sphere centre [m]
  double radius_m = 0.0;
  /// The visible surface point on the ray through the centre: centre - radius * centre / |centre| [m]. This is
  /// what a stereo camera measures at the boll's image centroid; the perception is scored against it.
  cv::Point3d surface;
  cv::Point2d pixel;              ///< projected centre [px]
  double radius_px = 0.0;         ///< projected radius [px]
  double visible_fraction = 0.0;  ///< share of its silhouette not hidden by leaves or the image border [0, 1]
};

/// The true end-effector: the centre of the top face of its orange housing.
struct TrueEndEffector {
  cv::Point3d top_centre;         ///< [m]
  cv::Point2d pixel;              ///< [px]
  double visible_fraction = 0.0;  ///< share of its top face not hidden by leaves or the image border [0, 1]
};

/// A random scene: its shapes and its truth (visible fractions are filled in by the renderer).
struct SceneLayout {
  std::vector<ScenePrimitive> primitives;
  std::vector<TrueBoll> bolls;
  std::optional<TrueEndEffector> end_effector;
  cv::Point3d sun_direction;         ///< unit vector towards the sun [-]
  double exposure = 1.0;             ///< camera gain of this frame [-]
  cv::Vec3f white_balance{1, 1, 1};  ///< BGR gains of this frame [-]
};

/// Returns an empty string when valid, otherwise what is wrong.
std::string validate(const SceneParams& params);

/// Draws a random cotton-row scene from `seed` (deterministic).
SceneLayout generateLayout(const SceneParams& params, std::uint32_t seed);

}  // namespace perception
}  // namespace cotton_harvester
