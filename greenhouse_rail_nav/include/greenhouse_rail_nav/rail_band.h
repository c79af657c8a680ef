#pragma once

#include <vector>

#include <Eigen/Core>

namespace greenhouse_rail_nav {

/// The points of a depth cloud in the rails' height band (base_link [m]), as the rail detector's stages use them:
/// thinned to voxels for clustering and line fitting, their x, y, and the band before thinning for the pipe axis fit.
struct RailBand {
  std::vector<Eigen::Vector3f> points;  ///< thinned to voxels
  std::vector<Eigen::Vector2d> xy;      ///< x, y of `points`, index for index
  std::vector<Eigen::Vector3f> raw;     ///< before thinning
};

/// One point per occupied voxel of side voxel_m (the mean of its points), so that near, dense parts of a rail do not
/// outweigh far ones and clustering gets fewer points. Voxels in the order of their x, y, z indices. voxel_m <= 0:
/// the points unchanged.
std::vector<Eigen::Vector3f> thinToVoxels(const std::vector<Eigen::Vector3f>& points, double voxel_m);

/// x, y of every point [m].
std::vector<Eigen::Vector2d> xyOf(const std::vector<Eigen::Vector3f>& points);
/// x, y of the points at `indices` [m].
std::vector<Eigen::Vector2d> xyOf(const std::vector<Eigen::Vector3f>& points, const std::vector<int>& indices);

/// Median z of the points at `indices` (the upper one of an even count) [m]; 0 without indices.
double medianHeight(const std::vector<Eigen::Vector3f>& points, const std::vector<int>& indices);

}  // namespace greenhouse_rail_nav
