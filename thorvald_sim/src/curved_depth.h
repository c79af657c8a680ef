// Exact depth of a pixel's ray on the curved geoms the camera draws tessellated (spheres, capsules, cylinders,
// ellipsoids).
#pragma once

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <cmath>

namespace thorvald_sim {

/// Smallest t >= 0 with |o + t d|^2 = r^2 (a sphere of radius r at the origin) folded into `best`.
inline void sphereHit(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double r, double* best) {
  const double a = d.squaredNorm(), b = o.dot(d), c = o.squaredNorm() - r * r;
  const double disc = b * b - a * c;
  if (disc < 0.0 || a <= 0.0) return;
  const double q = std::sqrt(disc);
  const double t = (-b - q) / a >= 0.0 ? (-b - q) / a : (-b + q) / a;
  if (t >= 0.0 && (*best < 0.0 || t < *best)) *best = t;
}

/// The side of a cylinder of radius r around z, between z = -h and h.
inline void sideHit(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double r, double h, double* best) {
  const double a = d.x() * d.x() + d.y() * d.y();
  if (a <= 0.0) return;
  const double b = o.x() * d.x() + o.y() * d.y(), c = o.x() * o.x() + o.y() * o.y() - r * r;
  const double disc = b * b - a * c;
  if (disc < 0.0) return;
  const double q = std::sqrt(disc);
  for (const double t : {(-b - q) / a, (-b + q) / a})
    if (t >= 0.0 && std::fabs(o.z() + t * d.z()) <= h && (*best < 0.0 || t < *best)) {
      *best = t;
      return;
    }
}

/// Where the ray o + t d (d: a pixel's ray (x, y, 1) turned into the geom frame, so t is the depth along the
/// optical axis) first meets the exact surface of a sphere, capsule, cylinder or ellipsoid; -1 for none. Other types:
/// -2 (the caller asks MuJoCo).
inline double curvedDepth(int type, const double* size, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  double best = -1.0;
  switch (type) {
    case mjGEOM_SPHERE:
      sphereHit(o, d, size[0], &best);
      return best;
    case mjGEOM_CAPSULE: {
      const double r = size[0], h = size[1];
      sideHit(o, d, r, h, &best);
      sphereHit(o - Eigen::Vector3d(0, 0, h), d, r, &best);
      sphereHit(o + Eigen::Vector3d(0, 0, h), d, r, &best);
      return best;
    }
    case mjGEOM_CYLINDER: {
      const double r = size[0], h = size[1];
      sideHit(o, d, r, h, &best);
      if (d.z() != 0.0)
        for (const double cap : {-h, h}) {
          const double t = (cap - o.z()) / d.z();
          const double px = o.x() + t * d.x(), py = o.y() + t * d.y();
          if (t >= 0.0 && px * px + py * py <= r * r && (best < 0.0 || t < best)) best = t;
        }
      return best;
    }
    case mjGEOM_ELLIPSOID: {  // the unit sphere in coordinates scaled by the semi-axes (t is unchanged)
      const Eigen::Vector3d inv(1.0 / size[0], 1.0 / size[1], 1.0 / size[2]);
      sphereHit(o.cwiseProduct(inv), d.cwiseProduct(inv), 1.0, &best);
      return best;
    }
    default:
      return -2.0;
  }
}

}  // namespace thorvald_sim
