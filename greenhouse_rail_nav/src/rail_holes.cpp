#include "greenhouse_rail_nav/rail_holes.h"

#include <cmath>
#include <vector>

namespace greenhouse_rail_nav {

OrganisedCloud holesOnPlane(const OrganisedCloud& cloud, const CloudProjection& projection,
                            const Eigen::Isometry3d& camera_in_base, double height_m) {
  OrganisedCloud out;
  out.width = cloud.width, out.height = cloud.height;
  const Eigen::Vector3f none = Eigen::Vector3f::Constant(NAN);
  out.points.assign(cloud.points.size(), none);
  if (cloud.points.size() != static_cast<std::size_t>(cloud.width) * static_cast<std::size_t>(cloud.height)) return out;
  std::vector<int> empty(static_cast<std::size_t>(cloud.width), 0);
  for (int v = 0; v < cloud.height; ++v)
    for (int u = 0; u < cloud.width; ++u)
      empty[u] += !cloud.points[static_cast<std::size_t>(v) * cloud.width + u].allFinite();
  const auto& k = projection.intrinsics();
  const Eigen::Matrix3d rot = camera_in_base.linear();
  const Eigen::Vector3d origin = camera_in_base.translation();
  const Eigen::Isometry3d base_in_camera = camera_in_base.inverse();
  for (int v = 0; v < cloud.height; ++v) {
    for (int u = 0; u < cloud.width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * cloud.width + u;
      if (cloud.points[i].allFinite() || 2 * empty[u] >= cloud.height) continue;
      const Eigen::Vector3d dir = rot * Eigen::Vector3d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
      if (!(dir.z() < -1e-9)) continue;  // the ray does not come down to the plane
      const double t = (height_m - origin.z()) / dir.z();
      if (t <= 0.0) continue;
      out.points[i] = (base_in_camera * (origin + t * dir)).cast<float>();
    }
  }
  return out;
}

}  // namespace greenhouse_rail_nav
