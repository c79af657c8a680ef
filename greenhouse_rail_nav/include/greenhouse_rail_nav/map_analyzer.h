#pragma once

#include <string>
#include <vector>

#include "greenhouse_rail_nav/line_extraction.h"
#include "greenhouse_rail_nav/occupancy_map.h"
#include "greenhouse_rail_nav/pose2d.h"

namespace greenhouse_rail_nav {

/// Settings of the headland map analysis (paper §V-B). Defaults: our greenhouse model (see README).
struct MapAnalyzerParams {
  double rail_set_spacing_m = 1.60;           ///< distance between the centres of neighbouring rail sets [m]
  double rail_gauge_m = 0.55;                 ///< centre distance of the two pipes of a rail set [m] (drawn only)
  Pose2D target_in_rail{-0.8, 0.0, 0.0};      ///< wanted robot pose in every rail frame (in front of the rails)
  double cluster_link_radius_m = 0.25;        ///< occupied cells closer than this form one cluster [m]
  int min_cluster_cells = 20;                 ///< smaller clusters are dropped
  LineExtractionParams lines;                 ///< straight-line thresholds
  double perpendicular_tolerance_rad = 0.08;  ///< rows must be this close to perpendicular to the rear wall
  double min_headland_depth_m = 1.0;          ///< rows start at least this far from the rear wall [m]
  double edge_tolerance_m = 0.5;    ///< a row whose start is farther than this from the common edge is not a row
  double spacing_tolerance = 0.25;  ///< allowed misfit of a gap to a multiple of the spacing [fraction of spacing]
  double keep_out_margin_m = 0.0;   ///< virtual wall this far beyond (positive) the headland edge [m]

  /// Empty if valid, else which key is wrong and what it must be.
  std::string validate() const;
};

/// One rail set found in the map.
struct RailSetEstimate {
  int index = 0;       ///< 0 = leftmost looking into the rows
  Pose2D rail_frame;   ///< origin between the rails at their start, x along the rails, in the map frame
  Pose2D target_pose;  ///< rail_frame * target_in_rail, in the map frame
};

/// Everything the analysis found, for the node, the markers and the tests.
struct MapAnalysis {
  bool ok = false;
  std::string message;                ///< what was found (and, on failure, what was expected)
  std::vector<std::string> warnings;  ///< things that look wrong but did not stop the analysis
  std::vector<LineSegment> lines;     ///< every straight line found
  int rear_wall = -1;                 ///< index into lines
  std::vector<int> rows;              ///< indices into lines of rows / ventilation lines, sorted along the edge
  Eigen::Vector2d edge_start = Eigen::Vector2d::Zero();  ///< headland edge end points in the map frame [m]
  Eigen::Vector2d edge_end = Eigen::Vector2d::Zero();
  Eigen::Vector2d into_rows = Eigen::Vector2d::UnitY();  ///< unit vector from the headland into the rows
  bool left_wall_found = false, right_wall_found = false;
  Eigen::Vector2d left_wall = Eigen::Vector2d::Zero();  ///< side wall points on the edge line [m]
  Eigen::Vector2d right_wall = Eigen::Vector2d::Zero();
  std::vector<RailSetEstimate> rail_sets;
};

/// Finds the rail sets in a headland map: clusters, line fits, rear wall, rows, headland edge, side walls,
/// rail-set count from the spacing, rail frames and target poses. Never invents poses: when no row or
/// rear wall is found, ok is false and message says what was found and what was expected.
MapAnalysis analyzeMap(const OccupancyMap& map, const MapAnalyzerParams& params);

}  // namespace greenhouse_rail_nav
