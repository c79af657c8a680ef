#include "greenhouse_rail_nav/pcl_backend.h"

#include <pcl/ModelCoefficients.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>
#include <pcl/segmentation/sac_segmentation.h>

namespace greenhouse_rail_nav {
namespace {

pcl::PointCloud<pcl::PointXYZ>::Ptr toPcl(const std::vector<Eigen::Vector3f>& points) {
  pcl::PointCloud<pcl::PointXYZ>::Ptr cloud(new pcl::PointCloud<pcl::PointXYZ>);
  cloud->points.reserve(points.size());
  for (const auto& p : points) cloud->points.emplace_back(p.x(), p.y(), p.z());
  cloud->width = static_cast<std::uint32_t>(points.size());
  cloud->height = 1;
  cloud->is_dense = true;
  return cloud;
}

}  // namespace

std::vector<std::vector<int>> euclideanClusters(const std::vector<Eigen::Vector3f>& points, double tolerance_m,
                                                int min_points, int max_points) {
  std::vector<std::vector<int>> clusters;
  if (points.empty()) return clusters;
  const auto cloud = toPcl(points);
  pcl::search::KdTree<pcl::PointXYZ>::Ptr tree(new pcl::search::KdTree<pcl::PointXYZ>);
  tree->setSortedResults(false);
  tree->setInputCloud(cloud);
  std::vector<pcl::PointIndices> found;
  pcl::EuclideanClusterExtraction<pcl::PointXYZ> extraction;
  extraction.setClusterTolerance(tolerance_m);
  extraction.setMinClusterSize(min_points);
  extraction.setMaxClusterSize(max_points);
  extraction.setSearchMethod(tree);
  extraction.setInputCloud(cloud);
  extraction.extract(found);
  for (auto& c : found) clusters.emplace_back(c.indices.begin(), c.indices.end());
  return clusters;
}

std::vector<RansacLine> ransacLines(const std::vector<Eigen::Vector3f>& points, double distance_m, int max_lines,
                                    int min_inliers, int max_iterations) {
  std::vector<RansacLine> lines;
  std::vector<int> remaining(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) remaining[i] = static_cast<int>(i);
  pcl::SACSegmentation<pcl::PointXYZ> segmentation(false);  // false: fixed seed, repeatable
  segmentation.setOptimizeCoefficients(false);
  segmentation.setModelType(pcl::SACMODEL_LINE);
  segmentation.setMethodType(pcl::SAC_RANSAC);
  segmentation.setDistanceThreshold(distance_m);
  segmentation.setMaxIterations(max_iterations);
  while (static_cast<int>(lines.size()) < max_lines && static_cast<int>(remaining.size()) >= min_inliers) {
    std::vector<Eigen::Vector3f> subset;
    subset.reserve(remaining.size());
    for (const int i : remaining) subset.push_back(points[static_cast<std::size_t>(i)]);
    segmentation.setInputCloud(toPcl(subset));
    pcl::PointIndices inliers;
    pcl::ModelCoefficients coefficients;
    segmentation.segment(inliers, coefficients);
    if (static_cast<int>(inliers.indices.size()) < min_inliers || coefficients.values.size() != 6) break;
    RansacLine line;
    line.point = Eigen::Vector3f(coefficients.values[0], coefficients.values[1], coefficients.values[2]);
    line.direction =
        Eigen::Vector3f(coefficients.values[3], coefficients.values[4], coefficients.values[5]).normalized();
    std::vector<bool> taken(subset.size(), false);
    for (const int i : inliers.indices) {
      taken[static_cast<std::size_t>(i)] = true;
      line.inliers.push_back(remaining[static_cast<std::size_t>(i)]);
    }
    std::vector<int> rest;
    for (std::size_t i = 0; i < subset.size(); ++i)
      if (!taken[i]) rest.push_back(remaining[i]);
    remaining.swap(rest);
    lines.push_back(std::move(line));
  }
  return lines;
}

}  // namespace greenhouse_rail_nav
