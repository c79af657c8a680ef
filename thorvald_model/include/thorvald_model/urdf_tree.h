#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

#include "thorvald_model/rigid_body.h"

namespace thorvald_model {

/// A primitive used both as visual and as collision geometry of a link.
struct Shape {
  enum class Kind { kBox, kCylinder };
  Kind kind = Kind::kBox;
  Eigen::Vector3d size_m = Eigen::Vector3d::Zero();   ///< box edges [m]
  double radius_m = 0.0;                              ///< cylinder radius [m]
  double length_m = 0.0;                              ///< cylinder length along its z axis [m]
  Eigen::Vector3d xyz_m = Eigen::Vector3d::Zero();    ///< origin in the link frame [m]
  Eigen::Vector3d rpy_rad = Eigen::Vector3d::Zero();  ///< orientation in the link frame [rad]
  std::string material;                               ///< one of the materials the writer declares
};

/// A URDF link: its shapes and the mass properties computed from them.
struct Link {
  std::string name;
  std::vector<Shape> shapes;
  MassProperties inertial;  ///< mass_kg == 0: no <inertial> element
};

/// A URDF joint. Axis and limits matter only for the joint types that use them.
struct Joint {
  std::string name;
  std::string type;  ///< fixed | revolute | continuous | floating
  std::string parent, child;
  Eigen::Vector3d xyz_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d rpy_rad = Eigen::Vector3d::Zero();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  double lower_rad = 0.0, upper_rad = 0.0;  ///< revolute only
  double effort = 0.0;                      ///< [N m], revolute/continuous
  double velocity = 0.0;                    ///< [rad/s], revolute/continuous
};

/// A whole robot: links and joints, the first link is the root.
struct UrdfTree {
  std::string robot_name;
  std::vector<Link> links;
  std::vector<Joint> joints;
  std::vector<std::string> warnings;  ///< things worth one log line each (adjusted geometry)

  double totalMassKg() const {
    double m = 0.0;
    for (const auto& l : links) m += l.inertial.mass_kg;
    return m;
  }
  const Link* findLink(const std::string& name) const {
    for (const auto& l : links)
      if (l.name == name) return &l;
    return nullptr;
  }
  const Joint* findJoint(const std::string& name) const {
    for (const auto& j : joints)
      if (j.name == name) return &j;
    return nullptr;
  }
};

}  // namespace thorvald_model
