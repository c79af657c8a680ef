#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "greenhouse_rail_nav/pcl_backend.h"
#include "greenhouse_rail_nav/rail_detector_params.h"
#include "greenhouse_rail_nav/rail_pair.h"

namespace greenhouse_rail_nav {

/// The rail detector's second stage: straight lines in the rails' band that may be rails, best first.
struct RailLineCandidates {
  std::vector<RailLine> lines;
  std::size_t groups = 0;  ///< clusters (or RANSAC lines) that were looked at
};

/// The rail of one Euclidean cluster of band points (indices into `band`, base_link [m]): the least-squares line of
/// its x, y when it is at least min_line_length_m long, at least min_linearity straight and heads within
/// max_abs_yaw_rad of the robot, trimmed to its points within rail_trim_m, at the cluster's median height. The
/// untrimmed fit's linearity ranks it. std::nullopt for any other cluster.
std::optional<RailLine> railLineFromCluster(const std::vector<Eigen::Vector3f>& band, const std::vector<int>& cluster,
                                            const RailDetectorParams& p);

/// The baseline's rail of one RANSAC line: RANSAC's own direction (oriented forward) through the mean of its inliers,
/// its extents and start (the 2 % quantile along it) from the inliers, at their median height. std::nullopt for a
/// near-vertical line, one shorter than min_line_length_m or one heading further than max_abs_yaw_rad.
std::optional<RailLine> railLineFromRansac(const std::vector<Eigen::Vector3f>& band, const RansacLine& line,
                                           const RailDetectorParams& p);

/// The paper's candidates: Euclidean clusters of the band (cluster_tolerance_m, min/max_cluster_points), a rail
/// per cluster (railLineFromCluster), most linear first.
RailLineCandidates clusterRailLines(const std::vector<Eigen::Vector3f>& band, const RailDetectorParams& p);

/// The baseline's candidates: sequential RANSAC lines (ransac_*), a rail per line (railLineFromRansac), most points
/// first.
RailLineCandidates ransacRailLines(const std::vector<Eigen::Vector3f>& band, const RailDetectorParams& p);

}  // namespace greenhouse_rail_nav
