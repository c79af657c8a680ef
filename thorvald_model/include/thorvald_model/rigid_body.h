#pragma once

#include <Eigen/Dense>
#include <vector>

namespace thorvald_model {

/// Mass properties of a body: mass [kg], centre of mass [m] and inertia about the centre of mass [kg m^2],
/// both expressed in the frame of the link that owns the body.
struct MassProperties {
  double mass_kg = 0.0;
  Eigen::Vector3d com_m = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
};

/// Solid box with edges `size` [m] along its own x, y, z, centred at its origin.
MassProperties solidBox(const Eigen::Vector3d& size_m, double mass_kg);

/// Solid cylinder of radius and length [m] about its own z axis, centred at its origin.
MassProperties solidCylinder(double radius_m, double length_m, double mass_kg);

/// Tube (hollow cylinder) with outer and inner radius and length [m] about its own z axis, centred.
MassProperties tube(double outer_radius_m, double inner_radius_m, double length_m, double mass_kg);

/// Moves a body's properties into the link frame: its own frame is rotated by `rotation` and its origin placed
/// at `origin_m`.
MassProperties placed(const MassProperties& body, const Eigen::Vector3d& origin_m,
                      const Eigen::Matrix3d& rotation = Eigen::Matrix3d::Identity());

/// The properties of several bodies rigidly joined (parallel-axis theorem about the common centre of mass).
MassProperties combine(const std::vector<MassProperties>& bodies);

}  // namespace thorvald_model
