#pragma once

#include <vector>

#include "greenhouse_rail_nav/cell_clustering.h"
#include "greenhouse_rail_nav/line_fit.h"

namespace greenhouse_rail_nav {

/// Thresholds that decide which clusters of a map are straight lines.
struct LineExtractionParams {
  double min_linearity = 0.95;    ///< least fit linearity (the paper's correlation test) of a line cluster
  double min_length_m = 1.0;      ///< shortest line kept [m]
  double split_inlier_m = 0.10;   ///< distance to a candidate line within which a cell belongs to it [m]
  double max_gap_m = 0.5;         ///< largest gap inside one segment when splitting a cluster [m]
  double merge_angle_rad = 0.05;  ///< collinear segments closer than this in direction are merged [rad]
  double merge_offset_m = 0.20;   ///< ... and closer than this sideways [m]
  int max_lines_per_cluster = 8;  ///< segments taken from one non-straight cluster (walls meeting at corners)
};

/// A straight piece of the map: the fit and the cells it was fitted to.
struct LineSegment {
  LineFit2D fit;
  std::vector<Eigen::Vector2d> points;
};

/// Least-squares line per cluster; a cluster that is not straight (walls joined at a corner) is split
/// into straight segments by sequential RANSAC (fixed seed, so results are repeatable) and each piece
/// refitted by least squares. Collinear segments (a row with a gap) are merged. Only segments passing
/// min_linearity and min_length_m are returned.
std::vector<LineSegment> extractLines(const std::vector<CellCluster>& clusters, const LineExtractionParams& params);

}  // namespace greenhouse_rail_nav
