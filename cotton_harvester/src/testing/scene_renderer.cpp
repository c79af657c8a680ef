#include "cotton_harvester/testing/scene_renderer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace cotton_harvester {
namespace perception {
namespace {

using Kind = ScenePrimitive::Kind;
using Shape = ScenePrimitive::Shape;

constexpr int kGroundLabel = -1;

/// Pixel rectangle that holds a shape's image, clipped to the image when `clip`.
cv::Rect pixelBounds(const ScenePrimitive& p, const CameraIntrinsics& k, double z, const cv::Point2d& shift,
                     bool clip) {
  const double extent = p.shape == Shape::kSphere ? p.radius : std::max(p.a, p.b);
  const double near_z = p.shape == Shape::kSphere ? std::max(1e-3, z - p.radius) : z;
  const cv::Point2d centre = project(k, {p.centre.x + shift.x, p.centre.y + shift.y, z});
  const double half = k.fx * extent / near_z * 1.2 + 2.0;
  cv::Rect box(static_cast<int>(std::floor(centre.x - half)), static_cast<int>(std::floor(centre.y - half)),
               static_cast<int>(std::ceil(2 * half)) + 1, static_cast<int>(std::ceil(2 * half)) + 1);
  if (clip) box &= cv::Rect(0, 0, k.width, k.height);
  return box;
}

/// Whether the horizontal shape covers the point (x, y) [m] when moved by shift.
bool planeCovers(const ScenePrimitive& p, double x, double y, const cv::Point2d& shift) {
  const double dx = x - p.centre.x - shift.x, dy = y - p.centre.y - shift.y;
  const double c = std::cos(p.angle_rad), s = std::sin(p.angle_rad);
  const double along = dx * c + dy * s, across = -dx * s + dy * c;
  if (p.shape == Shape::kRectangle) return std::abs(along) <= p.a && std::abs(across) <= p.b;
  const double ra = p.shape == Shape::kSphere ? p.radius : p.a, rb = p.shape == Shape::kSphere ? p.radius : p.b;
  return (along * along) / (ra * ra) + (across * across) / (rb * rb) <= 1.0;
}

/// Depth [m] at which the ray (rx, ry, 1) meets the sphere, or NaN.
double sphereHit(const ScenePrimitive& p, double rx, double ry) {
  const cv::Point3d d(rx, ry, 1.0);
  const double dc = d.dot(p.centre), dd = d.dot(d);
  const double disc = dc * dc - dd * (p.centre.dot(p.centre) - p.radius * p.radius);
  if (disc < 0.0) return std::numeric_limits<double>::quiet_NaN();
  return (dc - std::sqrt(disc)) / dd;
}

struct Light {
  double ambient, direct;
  cv::Vec3f tint;  // BGR white balance
};

Light lightOf(Lighting lighting) {
  switch (lighting) {
    case Lighting::kSunny:
      return Light{0.40, 0.75, {1.0f, 1.0f, 1.0f}};
    case Lighting::kCloudy:
      return Light{0.88, 0.0, {1.05f, 1.0f, 0.94f}};
    case Lighting::kShade:
      return Light{0.55, 0.0, {1.06f, 1.0f, 0.94f}};  // blue sky light, mostly corrected by auto white balance
  }
  return Light{0.88, 0.0, {1.0f, 1.0f, 1.0f}};
}

/// Reflectance of a boll at surface normal n: white lobes with creases, brown bracts at the silhouette.
cv::Vec3f bollAlbedo(const ScenePrimitive& p, const cv::Point3d& n) {
  if (-n.z < 0.35) return {0.20f, 0.30f, 0.36f};
  const double lobe = 0.88 + 0.12 * std::cos(5.0 * std::atan2(n.y, n.x) + p.centre.x * 40.0);
  return p.albedo * static_cast<float>(lobe);
}

}  // namespace

SyntheticFrame renderScene(const SceneLayout& layout, const SceneParams& params, std::uint32_t seed) {
  const std::string error = validate(params);
  if (!error.empty()) throw std::invalid_argument("synthetic scene parameters: " + error);
  const CameraIntrinsics& k = params.intrinsics;
  const int width = k.width, height = k.height;
  const double ground = params.camera_height_m;
  const Light light = lightOf(params.lighting);
  const cv::Point3d& sun = layout.sun_direction;
  cv::RNG rng(seed ^ 0x9e3779b9u);

  cv::Mat depth(height, width, CV_64F, cv::Scalar(ground));
  cv::Mat label(height, width, CV_32S, cv::Scalar(kGroundLabel));
  cv::Mat radiance(height, width, CV_32FC3);

  // Soil: smooth mottling plus fine grain.
  cv::Mat mottle(height / 16 + 1, width / 16 + 1, CV_32F);
  rng.fill(mottle, cv::RNG::UNIFORM, 0.75, 1.2);
  cv::resize(mottle, mottle, {width, height}, 0, 0, cv::INTER_CUBIC);
  const cv::Vec3f soil(0.28f, 0.40f, 0.54f);

  // Cast shadows on the soil (sunny): every shape moved along the sun's rays down to the ground.
  cv::Mat shadow(height, width, CV_8U, cv::Scalar(0));
  if (light.direct > 0.0) {
    for (const ScenePrimitive& p : layout.primitives) {
      if (p.kind == Kind::kGlint || p.kind == Kind::kStone) continue;
      const double t = (p.centre.z - ground) / sun.z;
      const cv::Point2d shift(-t * sun.x, -t * sun.y);
      const cv::Rect box = pixelBounds(p, k, ground, shift, true);
      for (int v = box.y; v < box.y + box.height; ++v) {
        for (int u = box.x; u < box.x + box.width; ++u) {
          const double x = (u - k.cx) / k.fx * ground, y = (v - k.cy) / k.fy * ground;
          if (planeCovers(p, x, y, shift)) shadow.at<uint8_t>(v, u) = 1;
        }
      }
    }
  }
  const double flat_light = light.ambient + light.direct * std::max(0.0, -sun.z);
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      const double l = shadow.at<uint8_t>(v, u) ? light.ambient : flat_light;
      radiance.at<cv::Vec3f>(v, u) = soil * static_cast<float>(mottle.at<float>(v, u) * l);
    }
  }

  // Shapes, nearest surface wins.
  for (size_t i = 0; i < layout.primitives.size(); ++i) {
    const ScenePrimitive& p = layout.primitives[i];
    const cv::Rect box = pixelBounds(p, k, p.centre.z, {0, 0}, true);
    for (int v = box.y; v < box.y + box.height; ++v) {
      for (int u = box.x; u < box.x + box.width; ++u) {
        const double rx = (u - k.cx) / k.fx, ry = (v - k.cy) / k.fy;
        double z = p.centre.z;
        cv::Vec3f colour;
        if (p.shape == Shape::kSphere) {
          z = sphereHit(p, rx, ry);
          if (!(z > 0.0) || z >= depth.at<double>(v, u)) continue;
          const cv::Point3d n = (cv::Point3d(rx * z, ry * z, z) - p.centre) / p.radius;
          colour = bollAlbedo(p, n) * static_cast<float>(light.ambient + light.direct * std::max(0.0, n.dot(sun)));
        } else {
          if (z >= depth.at<double>(v, u) || !planeCovers(p, rx * z, ry * z, {0, 0})) continue;
          colour = p.albedo * static_cast<float>(flat_light);
        }
        depth.at<double>(v, u) = z;
        label.at<int>(v, u) = static_cast<int>(i);
        radiance.at<cv::Vec3f>(v, u) = colour;
      }
    }
  }

  SyntheticFrame frame;
  frame.layout = layout;

  // Truth: how much of each boll's silhouette is visible.
  for (size_t i = 0; i < layout.primitives.size(); ++i) {
    const ScenePrimitive& p = layout.primitives[i];
    if (p.kind != Kind::kBoll) continue;
    const cv::Rect box = pixelBounds(p, k, p.centre.z, {0, 0}, false);
    int silhouette = 0, visible = 0;
    for (int v = box.y; v < box.y + box.height; ++v) {
      for (int u = box.x; u < box.x + box.width; ++u) {
        if (!(sphereHit(p, (u - k.cx) / k.fx, (v - k.cy) / k.fy) > 0.0)) continue;
        ++silhouette;
        if (u >= 0 && v >= 0 && u < width && v < height && label.at<int>(v, u) == static_cast<int>(i)) ++visible;
      }
    }
    frame.layout.bolls[p.boll_index].visible_fraction = silhouette > 0 ? double(visible) / silhouette : 0.0;
  }
  // Truth: how much of the end-effector's top face is visible.
  for (size_t i = 0; i < layout.primitives.size() && frame.layout.end_effector; ++i) {
    const ScenePrimitive& p = layout.primitives[i];
    if (p.kind != Kind::kEndEffector) continue;
    const cv::Rect box = pixelBounds(p, k, p.centre.z, {0, 0}, false);
    int face = 0, visible = 0;
    for (int v = box.y; v < box.y + box.height; ++v) {
      for (int u = box.x; u < box.x + box.width; ++u) {
        if (!planeCovers(p, (u - k.cx) / k.fx * p.centre.z, (v - k.cy) / k.fy * p.centre.z, {0, 0})) continue;
        ++face;
        if (u >= 0 && v >= 0 && u < width && v < height && label.at<int>(v, u) == static_cast<int>(i)) ++visible;
      }
    }
    frame.layout.end_effector->visible_fraction = face > 0 ? double(visible) / face : 0.0;
  }

  // Colour image: optics blur, white balance, sensor noise.
  cv::GaussianBlur(radiance, radiance, {3, 3}, 0.8);
  cv::Mat noise(height, width, CV_32FC3);
  rng.fill(noise, cv::RNG::NORMAL, 0.0, params.pixel_noise);
  cv::Mat scaled;
  const double gain = 255.0 * layout.exposure;
  cv::multiply(
      radiance,
      cv::Scalar(gain * light.tint[0] * layout.white_balance[0], gain * light.tint[1] * layout.white_balance[1],
                 gain * light.tint[2] * layout.white_balance[2]),
      scaled);
  scaled += noise;
  scaled.convertTo(frame.bgr, CV_8UC3);

  // Organised cloud along each pixel's ray, with stereo-like noise and holes.
  frame.cloud.create(height, width, CV_32FC3);
  cv::Mat depth_noise(height, width, CV_64F), holes(height, width, CV_64F);
  rng.fill(depth_noise, cv::RNG::NORMAL, 0.0, 1.0);
  rng.fill(holes, cv::RNG::UNIFORM, 0.0, 1.0);
  cv::Mat invalid(height, width, CV_8U, cv::Scalar(0));
  for (int i = 0; i < params.hole_blobs; ++i) {
    const cv::Point centre(rng.uniform(0, width), rng.uniform(0, height));
    const cv::Size axes(rng.uniform(6, 22), rng.uniform(6, 22));
    cv::ellipse(invalid, centre, axes, rng.uniform(0.0, 180.0), 0, 360, cv::Scalar(1), cv::FILLED);
  }
  if (params.invalid_left_columns > 0)
    invalid.colRange(0, std::min(width, params.invalid_left_columns)).setTo(cv::Scalar(1));
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int v = 0; v < height; ++v) {
    for (int u = 0; u < width; ++u) {
      cv::Vec3f& point = frame.cloud.at<cv::Vec3f>(v, u);
      if (invalid.at<uint8_t>(v, u) || holes.at<double>(v, u) < params.hole_fraction) {
        point = {nan, nan, nan};
        continue;
      }
      const double z0 = depth.at<double>(v, u);
      const double z = z0 + params.depth_noise_per_m2 * z0 * z0 * depth_noise.at<double>(v, u);
      point = {static_cast<float>((u - k.cx) / k.fx * z), static_cast<float>((v - k.cy) / k.fy * z),
               static_cast<float>(z)};
    }
  }
  return frame;
}

SyntheticFrame makeSyntheticFrame(const SceneParams& params, std::uint32_t seed) {
  return renderScene(generateLayout(params, seed), params, seed);
}

}  // namespace perception
}  // namespace cotton_harvester
