#pragma once

#include <cstdint>
#include <vector>

#include "thorvald_map/occupancy_grid.h"
#include "thorvald_base/pose2d.h"

namespace greenhouse_rail_nav {

/// A greenhouse headland as a robot's SLAM map would show it, for tests and benchmarks.
/// Layout frame: x across the greenhouse from the left side wall's inner face, y from the rear wall's
/// inner face towards the rows. Rail set i is centred at x = (i + 0.5) * spacing; rows (plants or
/// ventilation lines) can stand at x = j * spacing, j = 1 .. rail_sets - 1; the side walls are at
/// x = 0 and x = rail_sets * spacing.
struct GreenhouseLayout {
  int rail_sets = 8;
  double spacing_m = 1.6;                              ///< [m]
  double headland_depth_m = 4.0;                       ///< rear wall to the start of the rows [m]
  double visible_row_depth_m = 3.0;                    ///< how far the map shows into the rows [m]
  double resolution_m = 0.05;                          ///< [m/cell]
  thorvald_base::Pose2D layout_in_map{2.0, 3.0, 0.0};  ///< where the layout frame sits in the map frame
  double map_margin_m = 1.0;                           ///< unknown border around the greenhouse [m]
  std::vector<int> visible_rows;                       ///< row positions j shown; empty: each with row_probability
  double row_probability = 0.5;
  double ventilation_fraction = 0.5;         ///< share of rows drawn as thin solid lines (others: dotted plants)
  double wall_thickness_m = 0.15;            ///< [m]
  double row_start_jitter_m = 0.03;          ///< random shift of where a row's first cell is [m]
  double gap_probability = 0.3;              ///< chance a row has a gap
  int clutter_objects = 4;                   ///< boxes and trolleys on the headland floor
  double speckle_per_m2 = 0.02;              ///< isolated false occupied cells on the headland [1/m^2]
  double speckle_free_fraction = 0.0;        ///< share of all free cells turned into single false occupied cells
  int noise_lines = 0;                       ///< thin 1-2 m lines of false occupied cells on the headland, any angle
  bool clutter_in_line = false;              ///< a box on the headland just in front of a drawn row, in line with it
  bool side_walls = true;                    ///< false: neither side wall is in the map (overrides the two below)
  bool left_wall = true;                     ///< false: the left side wall is missing from the map
  bool right_wall = true;                    ///< false: the right side wall is missing from the map
  double floor_beyond_missing_wall_m = 1.0;  ///< free floor mapped beyond a missing side wall [m]
  /// Where a side wall is missing: true, the rear wall ends at the greenhouse's corner (the floor beyond it
  /// shows that it ends there); false, the rear wall runs on over all the floor mapped beyond.
  bool rear_wall_ends_at_corner = true;
  /// > 0: ventilation lines are tubes this wide as a laser maps them: a face of one cell on each side and at
  /// the front, unknown inside [m]
  double ventilation_width_m = 0.0;
  /// Row positions j whose tube is seen from its left path only: its right face, and the floor up to 0.15 m
  /// beyond it, are unknown except at its front (needs ventilation_width_m > 0 and the row drawn solid).
  std::vector<int> rows_seen_from_left_only;
  /// > 0: the wall at the far end of the rows is in the map this far beyond the mapped part of the rows
  /// (floor between), 0.3 m wider than the greenhouse on each side, with the side walls running on to it [m]
  double end_wall_gap_m = 0.0;
  double door_width_m = 0.0;  ///< > 0: a door of this width in each side wall on the headland (unknown beyond) [m]
  std::uint32_t seed = 1;
};

/// The map and the truth it was drawn from.
struct SyntheticGreenhouseMap {
  thorvald_map::OccupancyGrid map;
  std::vector<thorvald_base::Pose2D> rail_frames;  ///< true rail frames in the map frame, leftmost first
  std::vector<int> rows_drawn;                     ///< row positions j actually drawn
  Eigen::Vector2d edge_start, edge_end;            ///< true headland edge between the side walls [m]
};

SyntheticGreenhouseMap makeGreenhouseMap(const GreenhouseLayout& layout);

}  // namespace greenhouse_rail_nav
