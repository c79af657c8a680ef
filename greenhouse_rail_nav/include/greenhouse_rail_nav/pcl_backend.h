#pragma once

#include <vector>

#include <Eigen/Core>

namespace greenhouse_rail_nav {

/// The only place PCL is used (its headers are heavy to compile): Euclidean clustering for the
/// detector and sequential RANSAC line fitting for the baseline. Takes and returns plain types.

/// Groups points whose neighbours lie within tolerance_m (PCL EuclideanClusterExtraction, k-d tree).
/// Returns point indices per cluster, clusters outside [min_points, max_points] dropped.
std::vector<std::vector<int>> euclideanClusters(const std::vector<Eigen::Vector3f>& points, double tolerance_m,
                                                int min_points, int max_points);

/// A 3D line found by RANSAC: a point, a unit direction and the inlier indices.
struct RansacLine {
  Eigen::Vector3f point = Eigen::Vector3f::Zero();
  Eigen::Vector3f direction = Eigen::Vector3f::UnitX();
  std::vector<int> inliers;
};

/// Sequential RANSAC (PCL SACSegmentation, SACMODEL_LINE, fixed seed): fits a line, removes its inliers,
/// repeats up to max_lines times or until fewer than min_inliers remain.
std::vector<RansacLine> ransacLines(const std::vector<Eigen::Vector3f>& points, double distance_m, int max_lines,
                                    int min_inliers, int max_iterations);

}  // namespace greenhouse_rail_nav
