#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "thorvald_navigation/costmap.h"

namespace thorvald_navigation {

/// The convex hull of points in base_link [m], counter-clockwise: the outline a robot sweeps over the floor.
/// Fewer than 3 distinct points give a polygon that Footprint::check() refuses.
Footprint convexHullFootprint(std::vector<Eigen::Vector2d> points);

/// The robot's outline taken from its URDF (the namespace's robot_description, which thorvald_model's urdf_generator
/// writes from the robot file and its frame extras): every collision shape of every link under `base_link` (joints at
/// their zero position) projected onto the floor, and their convex hull. Boxes count with their 8 corners, cylinders
/// with 16 points round each end, spheres with 16 points round their equator.
struct UrdfFootprint {
  Footprint footprint;
  int shapes = 0;                    ///< collision shapes taken
  std::vector<std::string> skipped;  ///< links whose mesh shapes were left out (no geometry to project)
  std::string error;                 ///< not empty: no usable outline (why)
};
/// `base_link`: the link's name, or a name ending in "/<base_link>" (a tf_prefix).
UrdfFootprint footprintFromUrdf(const std::string& urdf_xml, const std::string& base_link);

}  // namespace thorvald_navigation
