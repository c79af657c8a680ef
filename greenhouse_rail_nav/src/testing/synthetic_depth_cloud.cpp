#include "greenhouse_rail_nav/testing/synthetic_depth_cloud.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace greenhouse_rail_nav {
namespace {

struct Sphere {
  Eigen::Vector3d centre;  // world [m]
  double radius;           // [m]
};

/// Ray (o + t*d, t = depth along the optical axis) against a pipe along x at (y, z), x in [0, length].
double hitPipe(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double y, double z, double r, double length) {
  const double oy = o.y() - y, oz = o.z() - z;
  const double a = d.y() * d.y() + d.z() * d.z();
  const double b = 2.0 * (d.y() * oy + d.z() * oz);
  const double c = oy * oy + oz * oz - r * r;
  const double disc = b * b - 4.0 * a * c;
  if (a <= 0.0 || disc < 0.0) return std::numeric_limits<double>::infinity();
  const double t = (-b - std::sqrt(disc)) / (2.0 * a);
  const double x = o.x() + t * d.x();
  return (t > 0.0 && x >= 0.0 && x <= length) ? t : std::numeric_limits<double>::infinity();
}

double hitSphere(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Sphere& s) {
  const Eigen::Vector3d oc = o - s.centre;
  const double a = d.squaredNorm(), b = 2.0 * d.dot(oc), c = oc.squaredNorm() - s.radius * s.radius;
  const double disc = b * b - 4.0 * a * c;
  if (disc < 0.0) return std::numeric_limits<double>::infinity();
  const double t = (-b - std::sqrt(disc)) / (2.0 * a);
  return t > 0.0 ? t : std::numeric_limits<double>::infinity();
}

std::vector<Sphere> makeLeaves(const DepthSceneParams& scene, std::mt19937* rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Sphere> leaves;
  const double half_gauge = 0.5 * scene.rail_gauge_m;
  for (const double row_y : {-0.5 * scene.rail_set_spacing_m, 0.5 * scene.rail_set_spacing_m}) {
    for (int i = 0; i < scene.leaves_per_row; ++i) {
      const bool low = unit(*rng) < scene.low_leaf_fraction;
      const double radius = 0.03 + 0.08 * unit(*rng);
      // Low leaves reach from the row towards the rails; high ones hang around the row.
      const double reach = low ? 0.35 : 0.2;
      const double y = row_y + reach * (2.0 * unit(*rng) - 1.0);
      const double z = low ? 0.04 + 0.08 * unit(*rng) : 0.15 + 1.6 * unit(*rng);
      const double x = 0.1 + 6.0 * unit(*rng);
      leaves.push_back({{x, y, z}, radius});
    }
  }
  for (int i = 0; i < scene.floor_debris; ++i) {
    const double y = (half_gauge - 0.08) * (2.0 * unit(*rng) - 1.0);
    leaves.push_back({{0.3 + 4.0 * unit(*rng), y, 0.0}, 0.03 + 0.03 * unit(*rng)});
  }
  return leaves;
}

}  // namespace

OrganisedCloud renderDepthCloud(const DepthSceneParams& scene, const thorvald_base::Pose2D& base_in_rail) {
  std::mt19937 rng(scene.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const auto& k = scene.intrinsics;
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
  base.linear() = Eigen::AngleAxisd(base_in_rail.yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  base.translation() = Eigen::Vector3d(base_in_rail.x, base_in_rail.y, 0.0);
  const Eigen::Isometry3d camera = base * scene.camera_in_base;  // optical frame in the world
  const Eigen::Isometry3d world_to_camera = camera.inverse();
  const Eigen::Vector3d o = camera.translation();
  const Eigen::Matrix3d rot = camera.linear();

  std::vector<double> pipes_y = {-0.5 * scene.rail_gauge_m, 0.5 * scene.rail_gauge_m};
  if (scene.neighbour_sets) {
    for (const double s : {-scene.rail_set_spacing_m, scene.rail_set_spacing_m}) {
      pipes_y.push_back(s - 0.5 * scene.rail_gauge_m);
      pipes_y.push_back(s + 0.5 * scene.rail_gauge_m);
    }
  }
  const double r = 0.5 * scene.pipe_diameter_m;
  std::vector<double> depth(static_cast<std::size_t>(k.width) * k.height, std::numeric_limits<double>::infinity());
  auto rayDir = [&](int u, int v) { return Eigen::Vector3d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0); };
  for (int v = 0; v < k.height; ++v) {
    for (int u = 0; u < k.width; ++u) {
      const Eigen::Vector3d d = rot * rayDir(u, v);
      double t = d.z() < 0.0 ? -o.z() / d.z() : std::numeric_limits<double>::infinity();
      for (const double y : pipes_y)
        t = std::min(t, hitPipe(o, d, y, scene.pipe_centre_height_m, r, scene.rail_length_m));
      depth[static_cast<std::size_t>(v) * k.width + u] = t;
    }
  }
  // Leaves: only the pixels inside each leaf's projected bounding box are tested.
  for (const auto& leaf : makeLeaves(scene, &rng)) {
    const Eigen::Vector3d c = world_to_camera * leaf.centre;
    if (c.z() <= leaf.radius + 0.05) continue;
    const double pr_u = k.fx * leaf.radius / (c.z() - leaf.radius), pr_v = k.fy * leaf.radius / (c.z() - leaf.radius);
    const double pu = k.fx * c.x() / c.z() + k.cx, pv = k.fy * c.y() / c.z() + k.cy;
    const int u0 = std::max(0, static_cast<int>(pu - pr_u)),
              u1 = std::min(k.width - 1, static_cast<int>(pu + pr_u) + 1);
    const int v0 = std::max(0, static_cast<int>(pv - pr_v)),
              v1 = std::min(k.height - 1, static_cast<int>(pv + pr_v) + 1);
    for (int v = v0; v <= v1; ++v) {
      for (int u = u0; u <= u1; ++u) {
        double& t = depth[static_cast<std::size_t>(v) * k.width + u];
        t = std::min(t, hitSphere(o, rot * rayDir(u, v), leaf));
      }
    }
  }
  // Sensor effects: range limits, noise growing with depth^2, outliers, dropouts.
  std::vector<bool> dropped(depth.size(), false);
  for (int b = 0; b < scene.dropout_blobs; ++b) {
    const int w = 10 + static_cast<int>(40 * unit(rng)), h = 10 + static_cast<int>(30 * unit(rng));
    const int u0 = static_cast<int>(unit(rng) * k.width), v0 = static_cast<int>(unit(rng) * k.height);
    const int bw = std::max(1, w * k.width / 640), bh = std::max(1, h * k.height / 480);
    for (int v = v0; v < std::min(k.height, v0 + bh); ++v)
      for (int u = u0; u < std::min(k.width, u0 + bw); ++u) dropped[static_cast<std::size_t>(v) * k.width + u] = true;
  }
  OrganisedCloud cloud;
  cloud.width = k.width;
  cloud.height = k.height;
  cloud.points.assign(depth.size(), Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN()));
  for (int v = 0; v < k.height; ++v) {
    for (int u = 0; u < k.width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * k.width + u;
      double t = depth[i];
      const bool drop = dropped[i] || unit(rng) < scene.dropout_fraction;
      const double noise = gauss(rng), outlier = unit(rng);
      if (drop || !(t >= scene.min_range_m && t <= scene.max_range_m)) continue;
      t += scene.depth_noise_per_m2 * t * t * noise;
      if (outlier < scene.outlier_fraction) t *= 0.6 + 0.4 * unit(rng);
      cloud.points[i] = (t * rayDir(u, v)).cast<float>();
    }
  }
  return cloud;
}

}  // namespace greenhouse_rail_nav
