#include "thorvald_sim/ray_caster.h"

#include <Eigen/Geometry>
#include <cmath>

namespace thorvald_sim {

RayCaster::RayCaster(const mjModel* model, const mjData* data, int own_root_body)
    : m_(model), d_(data), own_root_(own_root_body) {}

void RayCaster::prepare(const Eigen::Vector3d& origin, double range, const Eigen::Vector3d& axis,
                        double half_angle_rad) {
  candidates_.clear();
  for (int g = 0; g < m_->ngeom; ++g) {
    if (own_root_ >= 0 && m_->body_rootid[m_->geom_bodyid[g]] == own_root_) continue;
    if (m_->geom_rgba[4 * g + 3] == 0.0f) continue;  // invisible
    if (m_->geom_type[g] == mjGEOM_PLANE) {
      candidates_.push_back(g);
      continue;
    }
    const Eigen::Vector3d c(d_->geom_xpos[3 * g], d_->geom_xpos[3 * g + 1], d_->geom_xpos[3 * g + 2]);
    const double rb = m_->geom_rbound[g];
    const Eigen::Vector3d v = c - origin;
    const double dist = v.norm();
    if (dist - rb > range) continue;
    if (dist > rb && half_angle_rad < M_PI) {
      const double angle = std::acos(std::max(-1.0, std::min(1.0, v.dot(axis) / dist)));
      if (angle > half_angle_rad + std::asin(std::min(1.0, rb / dist))) continue;
    }
    candidates_.push_back(g);
  }
}

double RayCaster::cast(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, int* geom) const {
  return castAmong(origin, dir, candidates_.data(), candidates_.data() + candidates_.size(), geom);
}

double RayCaster::castAmong(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir, const int* first,
                            const int* last, int* geom) const {
  double best = -1.0;
  int best_geom = -1;
  const mjtNum pnt[3] = {origin.x(), origin.y(), origin.z()}, vec[3] = {dir.x(), dir.y(), dir.z()};
  for (const int* it = first; it != last; ++it) {
    const int g = *it;
    const int type = m_->geom_type[g];
    if (type != mjGEOM_PLANE) {
      // Bounding sphere first: skip geoms the ray passes by.
      const Eigen::Vector3d c(d_->geom_xpos[3 * g], d_->geom_xpos[3 * g + 1], d_->geom_xpos[3 * g + 2]);
      const Eigen::Vector3d v = c - origin;
      const double along = v.dot(dir);
      const double rb = m_->geom_rbound[g];
      if ((v - along * dir).squaredNorm() > rb * rb) continue;
      if (along + rb < 0.0) continue;
      if (best >= 0.0 && along - rb > best) continue;
    }
    double x;
    if (type == mjGEOM_MESH)
      x = mj_rayMesh(m_, d_, g, pnt, vec);
    else if (type == mjGEOM_HFIELD)
      x = mj_rayHfield(m_, d_, g, pnt, vec);
    else
      x = mju_rayGeom(d_->geom_xpos + 3 * g, d_->geom_xmat + 9 * g, m_->geom_size + 3 * g, pnt, vec, type);
    if (x >= 0.0 && (best < 0.0 || x < best)) {
      best = x;
      best_geom = g;
    }
  }
  if (geom) *geom = best_geom;
  return best;
}

Eigen::Vector3d RayCaster::normal(int g, const Eigen::Vector3d& point, const Eigen::Vector3d& dir) const {
  const Eigen::Vector3d c(d_->geom_xpos[3 * g], d_->geom_xpos[3 * g + 1], d_->geom_xpos[3 * g + 2]);
  Eigen::Matrix3d R;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) R(i, j) = d_->geom_xmat[9 * g + 3 * i + j];
  return geomNormal(m_->geom_type[g], m_->geom_size + 3 * g, R, c, point, dir);
}

Eigen::Vector3d geomNormal(int type, const mjtNum* s, const Eigen::Matrix3d& R, const Eigen::Vector3d& c,
                           const Eigen::Vector3d& point, const Eigen::Vector3d& dir) {
  const Eigen::Vector3d p = R.transpose() * (point - c);  // in the geom's frame
  Eigen::Vector3d n;
  switch (type) {
    case mjGEOM_PLANE:
      n = Eigen::Vector3d::UnitZ();
      break;
    case mjGEOM_SPHERE:
      n = p;
      break;
    case mjGEOM_CAPSULE:
      n = Eigen::Vector3d(p.x(), p.y(), p.z() - std::max(-s[1], std::min(s[1], p.z())));
      break;
    case mjGEOM_ELLIPSOID:
      n = Eigen::Vector3d(p.x() / (s[0] * s[0]), p.y() / (s[1] * s[1]), p.z() / (s[2] * s[2]));
      break;
    case mjGEOM_CYLINDER:
      n = std::fabs(std::fabs(p.z()) - s[1]) < 1e-6 ? Eigen::Vector3d(0, 0, p.z()) : Eigen::Vector3d(p.x(), p.y(), 0);
      break;
    case mjGEOM_BOX: {
      int k = 0;
      double best = 1e9;
      for (int i = 0; i < 3; ++i) {
        const double gap = std::fabs(std::fabs(p[i]) - s[i]);
        if (gap < best) best = gap, k = i;
      }
      n = Eigen::Vector3d::Zero();
      n[k] = p[k] >= 0 ? 1.0 : -1.0;
      break;
    }
    default:
      return -dir;
  }
  if (n.squaredNorm() < 1e-18) return -dir;
  n = (R * n).normalized();
  return n.dot(dir) > 0 ? Eigen::Vector3d(-n) : n;
}

}  // namespace thorvald_sim
