#pragma once

#include <string>
#include <vector>

#include "greenhouse_rail_nav/line_extraction.h"
#include "thorvald_map/occupancy_grid.h"
#include "thorvald_base/pose2d.h"

namespace greenhouse_rail_nav {

/// Settings of the headland map analysis (paper §V-B). Defaults: our greenhouse model (see README).
struct MapAnalyzerParams {
  double rail_set_spacing_m = 1.60;  ///< distance between the centres of neighbouring rail sets [m]
  double rail_gauge_m = 0.55;        ///< centre distance of the two pipes of a rail set [m] (drawn only)
  thorvald_base::Pose2D target_in_rail{-0.8, 0.0,
                                       0.0};  ///< wanted robot pose in every rail frame (in front of the rails)
  double cluster_link_radius_m = 0.25;        ///< occupied cells closer than this form one cluster [m]
  int min_cluster_cells = 20;                 ///< smaller clusters are dropped
  LineExtractionParams lines;                 ///< straight-line thresholds
  double perpendicular_tolerance_rad = 0.08;  ///< rows must be this close to perpendicular to the rear wall
  double min_headland_depth_m = 1.0;          ///< rows start at least this far from the rear wall [m]
  double edge_tolerance_m = 0.5;  ///< a row whose start is farther than this from the common edge is not a row
  double spacing_tolerance =
      0.05;  ///< a measured spacing off the configured one by more than this fraction is warned about
  double keep_out_margin_m = 0.0;           ///< virtual wall this far beyond (positive) the headland edge [m]
  double speckle_max_area_m2 = 0.012;       ///< groups of occupied cells smaller than this are noise [m^2]
  double speckle_link_radius_m = 0.15;      ///< occupied cells this close are one group for speckle removal [m]
  double spacing_search_ratio = 1.3;        ///< the spacing is searched in [configured / ratio, configured * ratio]
  double spacing_fit_tolerance_m = 0.08;    ///< a gap fits when within this of a whole number of spacings [m]
  double row_heading_tolerance_rad = 0.02;  ///< rows and the rear wall's normal must agree within this [rad]
  double edge_straightness_m = 0.10;        ///< RMS of the row starts about the headland edge [m]
  double side_wall_min_support = 0.3;  ///< share of the scanlines across the headland that must stop at a side wall
  /// Where no side wall is found, the rear wall's end (with floor mapped beyond it) bounds the greenhouse
  /// when it lies a whole number of spacings beyond the outermost row plus at most this (the unseen side
  /// wall's thickness at the corner) [m]
  double side_wall_max_thickness_m = 0.35;

  /// Empty if valid, else which key is wrong and what it must be.
  std::string validate() const;
};

/// One rail set found in the map.
struct RailSetEstimate {
  int index = 0;                      ///< 0 = leftmost looking into the rows
  thorvald_base::Pose2D rail_frame;   ///< origin between the rails at their start, x along the rails, in the map frame
  thorvald_base::Pose2D target_pose;  ///< rail_frame * target_in_rail, in the map frame
  bool good = true;                   ///< every check behind this set passed; a mission visits only good sets
  std::string reason;                 ///< why the set is uncertain (empty when good)
};

/// One check behind the result: what was measured, against what limit, and whether it passed.
struct AnalysisCheck {
  std::string name;  ///< e.g. spacing_regular, edge_straight
  bool passed = false;
  double value = 0.0;  ///< measured value (units in detail)
  double limit = 0.0;  ///< limit it was checked against
  std::string detail;
};

enum class MapStatus { kOk, kUncertain, kFailed };
const char* toString(MapStatus status);

/// Everything the analysis found, for the node, the markers and the tests.
struct MapAnalysis {
  bool ok = false;                        ///< rail sets were found (good or uncertain)
  MapStatus status = MapStatus::kFailed;  ///< kOk only when every check passed and every set is good
  double confidence = 0.0;                ///< share of the checks that passed, times the share of good sets, [0, 1]
  std::vector<AnalysisCheck> checks;      ///< every check behind the status
  std::string message;                    ///< what was found (and, on failure, what was expected)
  std::string uncertain_reasons;          ///< the failed checks, "; "-separated (empty when status is kOk)
  double spacing_m = 0.0;                 ///< rail-set spacing measured in the map (0 when not measured) [m]
  std::size_t speckle_cells_removed = 0;
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
  bool left_open = false, right_open = false;  ///< no side wall there: rail sets may go on beyond the last one
  /// No side wall found there, but the rear wall's end bounds the rail sets (then that side is not open)
  bool left_by_rear_wall_end = false, right_by_rear_wall_end = false;
  std::vector<RailSetEstimate> rail_sets;
};

/// Finds the rail sets in a headland map: speckle removal, clusters, line fits, rear wall, rows, headland
/// edge, side walls, the spacing, rail frames and target poses, and the checks behind them. Never invents
/// poses: when no row or rear wall is found, ok is false and message says what was found and what was
/// expected. Sets whose position rests on a failed check are marked uncertain with the reason.
MapAnalysis analyzeMap(const thorvald_map::OccupancyGrid& map, const MapAnalyzerParams& params);

}  // namespace greenhouse_rail_nav
