#include "thorvald_model/rigid_body.h"

namespace thorvald_model {

MassProperties solidBox(const Eigen::Vector3d& size_m, double mass_kg) {
  MassProperties p;
  p.mass_kg = mass_kg;
  const Eigen::Vector3d s2 = size_m.cwiseProduct(size_m);
  p.inertia.diagonal() << mass_kg / 12.0 * (s2.y() + s2.z()), mass_kg / 12.0 * (s2.x() + s2.z()),
      mass_kg / 12.0 * (s2.x() + s2.y());
  return p;
}

MassProperties solidCylinder(double radius_m, double length_m, double mass_kg) {
  return tube(radius_m, 0.0, length_m, mass_kg);
}

MassProperties tube(double outer_radius_m, double inner_radius_m, double length_m, double mass_kg) {
  MassProperties p;
  p.mass_kg = mass_kg;
  const double r2 = outer_radius_m * outer_radius_m + inner_radius_m * inner_radius_m;
  const double radial = mass_kg / 12.0 * (3.0 * r2 + length_m * length_m);
  p.inertia.diagonal() << radial, radial, mass_kg / 2.0 * r2;
  return p;
}

MassProperties placed(const MassProperties& body, const Eigen::Vector3d& origin_m, const Eigen::Matrix3d& rotation) {
  MassProperties p;
  p.mass_kg = body.mass_kg;
  p.com_m = origin_m + rotation * body.com_m;
  p.inertia = rotation * body.inertia * rotation.transpose();
  return p;
}

MassProperties combine(const std::vector<MassProperties>& bodies) {
  MassProperties total;
  for (const auto& b : bodies) {
    total.mass_kg += b.mass_kg;
    total.com_m += b.mass_kg * b.com_m;
  }
  if (total.mass_kg <= 0.0) return MassProperties{};
  total.com_m /= total.mass_kg;
  for (const auto& b : bodies) {
    const Eigen::Vector3d d = b.com_m - total.com_m;
    total.inertia += b.inertia + b.mass_kg * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
  }
  return total;
}

}  // namespace thorvald_model
