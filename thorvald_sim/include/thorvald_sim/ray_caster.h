#pragma once

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <vector>

namespace thorvald_sim {

/// Casts rays against the model's geoms as they are now (mju_rayGeom, mj_rayMesh), ignoring one robot's own
/// geoms so a sensor does not see the robot carrying it. `prepare` keeps only the geoms a sensor can reach
/// (within range and inside a cone around its axis), which makes cameras affordable in large worlds.
class RayCaster {
 public:
  /// `own_root_body`: root body of the robot carrying the sensor (-1: see everything).
  RayCaster(const mjModel* model, const mjData* data, int own_root_body);

  /// Keeps the geoms whose bounding sphere lies within `range` [m] of `origin` and inside the cone of half angle
  /// `half_angle_rad` around `axis` (unit). Planes are always kept.
  void prepare(const Eigen::Vector3d& origin, double range, const Eigen::Vector3d& axis, double half_angle_rad);

  /// Distance [m] along the unit direction to the nearest prepared geom, or -1 for none. `geom` gets its id.
  double cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, int* geom = nullptr) const;
  /// The same against the geoms `first` .. `last` only (a subset of the prepared ones, e.g. those a beam can meet).
  double castAmong(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, const int* first, const int* last,
                   int* geom = nullptr) const;
  const std::vector<int>& prepared() const { return candidates_; }

  /// Outward surface normal of `geom` at a point on it (world frame, unit). Planes, spheres, capsules, boxes,
  /// cylinders and ellipsoids exactly; other shapes: towards the ray's origin.
  Eigen::Vector3d normal(int geom, const Eigen::Vector3d& point, const Eigen::Vector3d& dir) const;

  size_t candidates() const { return candidates_.size(); }
  const mjModel* model() const { return m_; }
  const mjData* data() const { return d_; }

 private:
  const mjModel* m_;
  const mjData* d_;
  int own_root_;
  std::vector<int> candidates_;
};

/// Outward unit normal, facing the ray, of a geom of `type` and `size` with rotation `R` and centre `c` (world) at
/// a point on its surface; RayCaster::normal for a geom as it is now.
Eigen::Vector3d geomNormal(int type, const mjtNum* size, const Eigen::Matrix3d& R, const Eigen::Vector3d& c,
                           const Eigen::Vector3d& point, const Eigen::Vector3d& dir);

}  // namespace thorvald_sim
