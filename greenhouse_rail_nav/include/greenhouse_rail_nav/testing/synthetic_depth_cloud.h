#pragma once

#include <cstdint>

#include "greenhouse_rail_nav/depth_camera.h"
#include "thorvald_base/pose2d.h"

namespace greenhouse_rail_nav {

/// A greenhouse scene in front of a rail set, seen by an active-stereo depth camera, for tests and
/// benchmarks. World frame = the rail frame: origin between the two pipes at their start, x along them,
/// z up, floor at z = 0. Neighbouring rail sets at +-spacing, rows of plants between the sets.
struct DepthSceneParams {
  DepthCameraIntrinsics intrinsics;
  /// True camera mount (optical frame in base_link); default: 0.35 m ahead of the axle, 0.70 m up,
  /// pitched 40 deg down.
  Eigen::Isometry3d camera_in_base = opticalFrameInBase(0.35, 0.0, 0.70, 0.70);
  double rail_gauge_m = 0.55;                   ///< centre distance of the pipes [m]
  double pipe_diameter_m = 0.051;               ///< [m]
  double pipe_centre_height_m = 0.03;           ///< above the floor [m] (pipe top 55 mm up: the rail wheel's step)
  double rail_length_m = 30.0;                  ///< [m]
  double rail_set_spacing_m = 1.6;              ///< [m]
  bool neighbour_sets = true;                   ///< draw the rail sets on either side
  int leaves_per_row = 250;                     ///< plants between the rail sets, as leaf spheres
  double low_leaf_fraction = 0.15;              ///< share of leaves hanging down into the rails' height band
  int floor_debris = 3;                         ///< fallen leaves on the floor between the rails
  double depth_noise_per_m2 = 0.003;            ///< depth noise sigma = this * depth^2 [1/m]
  double dropout_fraction = 0.03;               ///< pixels without depth, at random
  int dropout_blobs = 4;                        ///< patches without depth (glare, no texture)
  double outlier_fraction = 0.002;              ///< pixels with a wrong depth (flying pixels)
  double min_range_m = 0.2, max_range_m = 4.0;  ///< valid depth [m]
  std::uint32_t seed = 1;
};

/// Renders the organised cloud (optical frame) for base_link at base_in_rail (robot on the floor).
OrganisedCloud renderDepthCloud(const DepthSceneParams& scene, const thorvald_base::Pose2D& base_in_rail);

}  // namespace greenhouse_rail_nav
