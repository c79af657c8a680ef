#include "thorvald_navigation/robot_footprint.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <Eigen/Geometry>
#include <urdf_parser/urdf_parser.h>

namespace thorvald_navigation {

namespace {

double cross(const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

Eigen::Isometry3d toIsometry(const urdf::Pose& p) {
  double x = 0, y = 0, z = 0, w = 1;
  p.rotation.getQuaternion(x, y, z, w);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::Quaterniond(w, x, y, z).normalized().toRotationMatrix();
  t.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  return t;
}

/// Points on the surface of a collision shape in its own frame; false for a mesh.
bool shapePoints(const urdf::Geometry& g, std::vector<Eigen::Vector3d>* pts) {
  constexpr int kRound = 16;
  if (g.type == urdf::Geometry::BOX) {
    const auto& d = static_cast<const urdf::Box&>(g).dim;
    for (int i = 0; i < 8; ++i)
      pts->emplace_back((i & 1 ? 0.5 : -0.5) * d.x, (i & 2 ? 0.5 : -0.5) * d.y, (i & 4 ? 0.5 : -0.5) * d.z);
    return true;
  }
  if (g.type == urdf::Geometry::CYLINDER || g.type == urdf::Geometry::SPHERE) {
    const bool cyl = g.type == urdf::Geometry::CYLINDER;
    const double r = cyl ? static_cast<const urdf::Cylinder&>(g).radius : static_cast<const urdf::Sphere&>(g).radius;
    const double half = cyl ? 0.5 * static_cast<const urdf::Cylinder&>(g).length : 0.0;
    for (int i = 0; i < kRound; ++i) {
      // The polygon through these points lies inside the circle: push them out so that it encloses the circle.
      const double a = 2.0 * M_PI * i / kRound, rr = r / std::cos(M_PI / kRound);
      for (double z : {-half, half}) pts->emplace_back(rr * std::cos(a), rr * std::sin(a), z);
    }
    if (!cyl)  // a sphere: also round its other two great circles, so it projects as a disc at any orientation
      for (int i = 0; i < kRound; ++i) {
        const double a = 2.0 * M_PI * i / kRound, rr = r / std::cos(M_PI / kRound);
        pts->emplace_back(rr * std::cos(a), 0.0, rr * std::sin(a));
        pts->emplace_back(0.0, rr * std::cos(a), rr * std::sin(a));
      }
    return true;
  }
  return false;
}

}  // namespace

Footprint convexHullFootprint(std::vector<Eigen::Vector2d> points) {
  std::sort(points.begin(), points.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  points.erase(std::unique(points.begin(), points.end()), points.end());
  Footprint fp;
  if (points.size() < 3) {
    fp.polygon = points;
    return fp;
  }
  // Andrew's monotone chain: lower hull left to right, then upper hull right to left.
  std::vector<Eigen::Vector2d> hull(2 * points.size());
  std::size_t k = 0;
  for (const auto& p : points) {
    while (k >= 2 && cross(hull[k - 2], hull[k - 1], p) <= 1e-12) --k;
    hull[k++] = p;
  }
  for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && cross(hull[k - 2], hull[k - 1], points[i]) <= 1e-12) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);
  fp.polygon = hull;
  return fp;
}

UrdfFootprint footprintFromUrdf(const std::string& urdf_xml, const std::string& base_link) {
  UrdfFootprint out;
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(urdf_xml);
  if (!model) {
    out.error = "the robot description is not a URDF robot";
    return out;
  }
  urdf::LinkConstSharedPtr base;
  for (const auto& [name, link] : model->links_) {
    const bool prefixed = name.size() > base_link.size() &&
                          name.compare(name.size() - base_link.size() - 1, std::string::npos, "/" + base_link) == 0;
    if (name == base_link || prefixed) base = link;
  }
  if (!base) {
    out.error = "the robot description has no link " + base_link;
    return out;
  }
  std::vector<Eigen::Vector2d> floor;
  // Depth-first from base_link, each child at its joint's origin (the joint's zero position).
  std::vector<std::pair<urdf::LinkConstSharedPtr, Eigen::Isometry3d>> todo{{base, Eigen::Isometry3d::Identity()}};
  while (!todo.empty()) {
    const auto [link, pose] = todo.back();
    todo.pop_back();
    for (const auto& c : link->collision_array) {
      std::vector<Eigen::Vector3d> pts;
      if (!c || !c->geometry || !shapePoints(*c->geometry, &pts)) {
        out.skipped.push_back(link->name);
        continue;
      }
      ++out.shapes;
      const Eigen::Isometry3d at = pose * toIsometry(c->origin);
      for (const auto& p : pts) floor.push_back((at * p).head<2>());
    }
    for (const auto& j : link->child_joints)
      if (const auto child = model->getLink(j->child_link_name))
        todo.emplace_back(child, pose * toIsometry(j->parent_to_joint_origin_transform));
  }
  out.footprint = convexHullFootprint(floor);
  if (const std::string why = out.footprint.check(); !why.empty())
    out.error = "the collision shapes under " + base_link + " give no outline: " + why;
  return out;
}

}  // namespace thorvald_navigation
