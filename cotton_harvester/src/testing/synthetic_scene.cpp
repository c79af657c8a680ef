#include "cotton_harvester/testing/synthetic_scene.h"

#include <cmath>
#include <random>
#include <sstream>

namespace cotton_harvester {
namespace perception {
namespace {

using Kind = ScenePrimitive::Kind;
using Shape = ScenePrimitive::Shape;

class Draw {
 public:
  explicit Draw(std::uint32_t seed) : random_(seed) {}
  double uniform(double low, double high) { return std::uniform_real_distribution<double>(low, high)(random_); }
  int integer(int low, int high) { return std::uniform_int_distribution<int>(low, high)(random_); }
  bool chance(double p) { return uniform(0.0, 1.0) < p; }

 private:
  std::mt19937 random_;
};

ScenePrimitive flat(Shape shape, Kind kind, const cv::Point3d& centre, double a, double b, double angle,
                    const cv::Vec3f& albedo) {
  ScenePrimitive p;
  p.shape = shape;
  p.kind = kind;
  p.centre = centre;
  p.a = a;
  p.b = b;
  p.angle_rad = angle;
  p.albedo = albedo;
  return p;
}

/// A horizontal bar between two points at depth z.
ScenePrimitive bar(Kind kind, const cv::Point2d& from, const cv::Point2d& to, double z, double half_width,
                   const cv::Vec3f& albedo) {
  const cv::Point2d d = to - from;
  const cv::Point2d mid = 0.5 * (from + to);
  return flat(Shape::kRectangle, kind, {mid.x, mid.y, z}, 0.5 * std::hypot(d.x, d.y), half_width, std::atan2(d.y, d.x),
              albedo);
}

}  // namespace

std::optional<Lighting> parseLighting(const std::string& name) {
  if (name == "sunny") return Lighting::kSunny;
  if (name == "cloudy") return Lighting::kCloudy;
  if (name == "shade") return Lighting::kShade;
  return std::nullopt;
}

std::string toString(Lighting lighting) {
  switch (lighting) {
    case Lighting::kSunny:
      return "sunny";
    case Lighting::kCloudy:
      return "cloudy";
    case Lighting::kShade:
      return "shade";
  }
  return "?";
}

std::string validate(const SceneParams& p) {
  std::ostringstream error;
  const std::string camera = validate(p.intrinsics);
  if (!camera.empty()) error << camera;
  if (!(p.camera_height_m > 1.2)) error << "camera_height_m must be > 1.2 (plants reach 1.2 m); ";
  if (p.plants_min < 0 || p.plants_max < p.plants_min) error << "plants_min/max must satisfy 0 <= min <= max; ";
  if (p.bolls_per_plant_min < 0 || p.bolls_per_plant_max < p.bolls_per_plant_min)
    error << "bolls_per_plant_min/max must satisfy 0 <= min <= max; ";
  if (!(p.boll_radius_min_m > 0.0) || p.boll_radius_max_m < p.boll_radius_min_m)
    error << "boll radii must satisfy 0 < min <= max; ";
  if (!(p.boll_height_min_m > p.boll_radius_max_m) || p.boll_height_max_m < p.boll_height_min_m ||
      p.boll_height_max_m > p.camera_height_m - 0.3)
    error << "boll heights must lie between the ground and 0.3 m below the camera; ";
  if (!(p.hole_fraction >= 0.0 && p.hole_fraction <= 1.0)) error << "hole_fraction must be in [0, 1]; ";
  if (!(p.end_effector_probability >= 0.0 && p.end_effector_probability <= 1.0))
    error << "end_effector_probability must be in [0, 1]; ";
  if (!(p.exposure_min > 0.0 && p.exposure_max >= p.exposure_min)) error << "exposure must satisfy 0 < min <= max; ";
  if (!(p.white_balance_jitter >= 0.0 && p.white_balance_jitter < 0.5))
    error << "white_balance_jitter must be in [0, 0.5); ";
  if (p.clutter_items < 0 || p.clutter_items > 100) error << "clutter_items must be in [0, 100]; ";
  for (const double share : {p.end_effector_sheen_max, p.touching_probability, p.leaf_over_boll_probability})
    if (!(share >= 0.0 && share <= 1.0)) error << "end_effector_sheen_max and the probabilities must be in [0, 1]; ";
  return error.str();
}

SceneLayout generateLayout(const SceneParams& params, std::uint32_t seed) {
  Draw draw(seed);
  SceneLayout layout;
  const double ground = params.camera_height_m;
  layout.sun_direction = params.lighting == Lighting::kSunny ? cv::Point3d(0.35, -0.25, -1.0) : cv::Point3d(0, 0, -1);
  layout.sun_direction /= std::sqrt(layout.sun_direction.dot(layout.sun_direction));
  layout.exposure = draw.uniform(params.exposure_min, params.exposure_max);
  for (int c = 0; c < 3; ++c)
    layout.white_balance[c] =
        static_cast<float>(1.0 + draw.uniform(-params.white_balance_jitter, params.white_balance_jitter));

  // End-effector first, so that bolls keep clear of it.
  if (draw.chance(params.end_effector_probability)) {
    const cv::Point3d top(draw.uniform(-0.45, 0.45), draw.uniform(-0.45, 0.45), draw.uniform(1.15, 1.85));
    const double post_x = -0.80;
    layout.primitives.push_back(
        bar(Kind::kArm, {post_x, top.y}, {top.x - 0.06, top.y}, top.z + 0.004, 0.022, {0.62f, 0.62f, 0.60f}));
    const float sheen = params.lighting == Lighting::kSunny
                            ? static_cast<float>(draw.uniform(0.0, params.end_effector_sheen_max))
                            : 0.0f;
    const cv::Vec3f orange = cv::Vec3f(0.02f, 0.47f, 1.0f) * (1.0f - sheen) + cv::Vec3f(1.0f, 1.0f, 1.0f) * sheen;
    layout.primitives.push_back(flat(Shape::kRectangle, Kind::kEndEffector, top, 0.06, 0.05, 0.0, orange));
    layout.primitives.push_back(
        flat(Shape::kRectangle, Kind::kPost, {post_x, top.y, 0.6}, 0.035, 0.035, 0.0, {0.12f, 0.12f, 0.12f}));
    layout.end_effector = TrueEndEffector{top, project(params.intrinsics, top), 0.0};
  }

  const int plants = draw.integer(params.plants_min, params.plants_max);
  const double row_x = draw.uniform(-params.row_offset_max_m, params.row_offset_max_m);
  const double first_y = -0.5 * (plants - 1) * params.plant_spacing_m + draw.uniform(-0.1, 0.1);
  for (int plant = 0; plant < plants; ++plant) {
    const cv::Point2d stem(row_x + draw.uniform(-0.05, 0.05),
                           first_y + plant * params.plant_spacing_m + draw.uniform(-0.04, 0.04));
    const double plant_height = draw.uniform(std::max(0.9, params.boll_height_max_m), 1.2);

    const int bolls = draw.integer(params.bolls_per_plant_min, params.bolls_per_plant_max);
    const size_t first_boll = layout.bolls.size();
    for (int i = 0, attempts = 0; i < bolls && attempts < 50 * (bolls + 1); ++attempts) {
      const double radius = draw.uniform(params.boll_radius_min_m, params.boll_radius_max_m);
      const double height = draw.uniform(params.boll_height_min_m, std::min(params.boll_height_max_m, plant_height));
      const double spread = params.canopy_radius_m * 0.9 * std::sqrt(draw.uniform(0.05, 1.0));
      const double heading = draw.uniform(-CV_PI, CV_PI);
      cv::Point3d centre(stem.x + spread * std::cos(heading), stem.y + spread * std::sin(heading), ground - height);
      // A touching neighbour: beside the plant's previous boll, at about its height, the two silhouettes meeting.
      const bool touching = layout.bolls.size() > first_boll && draw.chance(params.touching_probability);
      if (touching) {
        const TrueBoll& previous = layout.bolls.back();
        const double gap = (previous.radius_m + radius) * draw.uniform(0.92, 1.02);
        centre = previous.centre +
                 cv::Point3d(gap * std::cos(heading), gap * std::sin(heading), draw.uniform(-0.3, 0.3) * radius);
      }
      bool clear = true;
      for (size_t j = 0; j < layout.bolls.size(); ++j) {
        const TrueBoll& other = layout.bolls[j];
        const cv::Point3d d = other.centre - centre;
        const double margin = touching && j + 1 == layout.bolls.size() ? -0.1 * (other.radius_m + radius) : 0.03;
        clear = clear && std::sqrt(d.dot(d)) > other.radius_m + radius + margin;
      }
      if (layout.end_effector) {
        const cv::Point3d d = layout.end_effector->top_centre - centre;
        clear = clear && std::hypot(d.x, d.y) > 0.12 + radius;
      }
      if (!clear) continue;
      ++i;

      TrueBoll boll;
      boll.centre = centre;
      boll.radius_m = radius;
      boll.surface = centre - radius * centre / std::sqrt(centre.dot(centre));
      boll.pixel = project(params.intrinsics, centre);
      boll.radius_px = params.intrinsics.fx * radius / centre.z;
      ScenePrimitive sphere;
      sphere.shape = Shape::kSphere;
      sphere.kind = Kind::kBoll;
      sphere.centre = centre;
      sphere.radius = radius;
      const float white = static_cast<float>(draw.uniform(0.90, 0.97));
      sphere.albedo = {white + 0.01f, white, white - 0.01f};
      sphere.boll_index = static_cast<int>(layout.bolls.size());
      layout.bolls.push_back(boll);
      layout.primitives.push_back(sphere);
      // The branch that carries it, just below the boll.
      layout.primitives.push_back(
          bar(Kind::kStem, stem, {centre.x, centre.y}, centre.z + 0.8 * radius, 0.006, {0.22f, 0.33f, 0.40f}));
      if (draw.chance(params.leaf_over_boll_probability)) {
        // A leaf just above the boll, its edge across the boll's silhouette.
        const double a = draw.uniform(0.04, 0.07);
        const double offset = a + radius * draw.uniform(-0.4, 0.6);
        const double towards = draw.uniform(-CV_PI, CV_PI);
        const cv::Point3d leaf(centre.x + offset * std::cos(towards), centre.y + offset * std::sin(towards),
                               centre.z - radius - draw.uniform(0.01, 0.05));
        const cv::Vec3f green(static_cast<float>(draw.uniform(0.08, 0.18)),
                              static_cast<float>(draw.uniform(0.38, 0.52)),
                              static_cast<float>(draw.uniform(0.12, 0.24)));
        layout.primitives.push_back(flat(Shape::kEllipse, Kind::kLeaf, leaf, a, a * draw.uniform(0.6, 0.9),
                                         draw.uniform(-CV_PI, CV_PI), green));
      }
    }

    for (int leaf = 0; leaf < params.leaves_per_plant; ++leaf) {
      const double spread = params.canopy_radius_m * std::sqrt(draw.uniform(0.0, 1.0));
      const double heading = draw.uniform(-CV_PI, CV_PI);
      const double a = draw.uniform(0.04, 0.08);
      const cv::Point3d centre(stem.x + spread * std::cos(heading), stem.y + spread * std::sin(heading),
                               ground - draw.uniform(0.3, plant_height));
      const cv::Vec3f green(static_cast<float>(draw.uniform(0.08, 0.18)), static_cast<float>(draw.uniform(0.38, 0.52)),
                            static_cast<float>(draw.uniform(0.12, 0.24)));
      const double angle = draw.uniform(-CV_PI, CV_PI);
      layout.primitives.push_back(
          flat(Shape::kEllipse, Kind::kLeaf, centre, a, a * draw.uniform(0.6, 0.9), angle, green));
      if (params.lighting == Lighting::kSunny && draw.chance(0.25)) {
        // Specular glint: bright, colourless, thin.
        const double g = draw.uniform(0.010, 0.02);
        layout.primitives.push_back(flat(Shape::kEllipse, Kind::kGlint, centre - cv::Point3d(0, 0, 0.001), g, g * 0.3,
                                         angle, {0.93f, 0.96f, 0.94f}));
      }
    }
  }

  // Pale stones on the soil: bright and colourless, but small.
  for (int i = 0; i < 8; ++i) {
    const double r = draw.uniform(0.006, 0.016);
    layout.primitives.push_back(flat(Shape::kEllipse, Kind::kStone,
                                     {draw.uniform(-1.3, 1.3), draw.uniform(-0.8, 0.8), ground - 0.005}, r,
                                     r * draw.uniform(0.6, 1.0), draw.uniform(-CV_PI, CV_PI), {0.55f, 0.60f, 0.66f}));
  }
  // White clutter, drawn last so that the rest of the scene does not depend on it.
  for (int i = 0; i < params.clutter_items; ++i) {
    const cv::Point2d at(draw.uniform(-1.0, 1.0), draw.uniform(-0.6, 0.6));
    const double angle = draw.uniform(-CV_PI, CV_PI);
    const float white = static_cast<float>(draw.uniform(0.80, 0.95));
    switch (draw.integer(0, 3)) {
      case 0: {  // a plant label on a stake
        const double a = draw.uniform(0.02, 0.05);
        layout.primitives.push_back(flat(Shape::kRectangle, Kind::kClutter,
                                         {at.x, at.y, ground - draw.uniform(0.3, 1.0)}, a, a * draw.uniform(0.4, 0.8),
                                         angle, {white, white, white}));
        break;
      }
      case 1: {  // a plastic bag caught in a plant
        const double a = draw.uniform(0.04, 0.10);
        layout.primitives.push_back(flat(Shape::kEllipse, Kind::kClutter, {at.x, at.y, ground - draw.uniform(0.2, 0.9)},
                                         a, a * draw.uniform(0.5, 0.9), angle, {white, white, white}));
        break;
      }
      case 2: {  // a piece of aluminium (a pipe, a frame's bar)
        const float grey = 0.8f * white;
        layout.primitives.push_back(flat(Shape::kRectangle, Kind::kClutter,
                                         {at.x, at.y, ground - draw.uniform(0.02, 0.5)}, draw.uniform(0.10, 0.30),
                                         draw.uniform(0.008, 0.02), angle, {grey, grey, grey * 0.98f}));
        break;
      }
      default: {  // a large white stone
        const double a = draw.uniform(0.02, 0.05);
        layout.primitives.push_back(flat(Shape::kEllipse, Kind::kClutter, {at.x, at.y, ground - 0.01}, a,
                                         a * draw.uniform(0.6, 1.0), angle, {white, white, white}));
        break;
      }
    }
  }
  return layout;
}

}  // namespace perception
}  // namespace cotton_harvester
