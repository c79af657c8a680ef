#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "thorvald_sim/greenhouse_variation.h"
#include "thorvald_sim/world_description.h"

namespace thorvald_sim {

/// The greenhouse of the rail robot paper (§II, §V). World frame: origin on the headland edge, x along the rows
/// (rows at x > 0, headland at x < 0), y across, z = 0 the headland floor's top.
struct GreenhouseParams {
  int rail_sets = 6;                ///< number of rail sets (one per path between plant rows)
  double set_spacing_m = 1.6;       ///< between the centres of neighbouring rail sets [m]
  double rail_gauge_m = 0.55;       ///< between the centres of the two pipes of a set [m]
  double pipe_diameter_m = 0.051;   ///< heating pipe diameter [m]
  double rail_top_m = 0.055;        ///< top of the pipes above the headland floor [m]
  double rail_length_m = 20.0;      ///< length of the rails [m]
  double rail_start_gap_m = 0.03;   ///< from the edge to where the pipes start [m]
  double support_spacing_m = 2.0;   ///< between pipe supports [m]
  double headland_depth_m = 6.0;    ///< from the edge to the rear wall [m]
  double row_ground_drop_m = 0.15;  ///< the rows' ground lies this far below the headland floor [m]
  double plant_bottom_m = 0.9;      ///< plant rows hang from here up to plant_top_m [m]
  double plant_top_m = 2.5;
  double plant_width_m = 0.35;
  /// The plants of a row begin this far past the rails' start and end this far before the end of the shorter rail
  /// set beside them [m]: trolleys, and the robot's lamps, stand on the rails beside the first and the last plant.
  double plant_row_start_m = 1.0;
  double plant_row_end_gap_m = 1.0;
  int vent_every = 2;           ///< a ventilation/heating line under every n-th plant row (0: none)
  double vent_height_m = 0.45;  ///< centre height of the ventilation lines [m]
  double vent_diameter_m = 0.3;
  double wall_margin_m = 1.2;  ///< from the outer rail sets' centres to the side walls [m]
  double wall_height_m = 3.0;
  GreenhouseVariation variation;  ///< all off by default: the ideal greenhouse
};

/// Colour of rusty pipe pieces (named `rusty_rail...`, so the depth camera's `rail` shiny prefix skips them).
constexpr const char* kRustyPipeColour = "0.42 0.2 0.09 1";

/// Where a rail set starts: its frame (between the pipes, at their start, x along the rails).
struct RailSetTruth {
  int index = 0;
  double start_x = 0, start_y = 0;  ///< [m]
  double yaw = 0;                   ///< [rad]
  double pipe_y[2] = {0, 0};        ///< centre lines of the two pipes [m]
  double length_m = 0;              ///< of its pipes [m]
  /// Sideways offset of each pipe's start end from its line [m]; the pipe bends back onto the line at
  /// start_x + bend_length_m (0: straight).
  double pipe_start_offset_m[2] = {0, 0};
  double bend_length_m = 0;
  /// The plants beside the set (both its rows), along it from its start [m]; to <= from: no plants beside it.
  double plants_from_m = 0, plants_to_m = 0;
};

/// Something left in the greenhouse (a crate, a parked trolley, a hose): a box or a lying capsule.
struct GreenhouseObstacle {
  std::string name, kind;                              ///< geom name, "crate" | "trolley" | "hose"
  double x = 0, y = 0, yaw = 0;                        ///< centre on the floor [m], heading [rad]
  double half_length = 0, half_width = 0, height = 0;  ///< [m]
};

/// What the greenhouse generator knows for sure, for tests and for the missions' ground truth.
struct GreenhouseTruth {
  GreenhouseParams params;
  double edge_x = 0.0;  ///< the headland edge is the line x = edge_x between edge_y_min and _max
  double edge_y_min = 0.0, edge_y_max = 0.0;
  double floor_z = 0.0, row_ground_z = 0.0, pipe_centre_z = 0.0;
  std::vector<RailSetTruth> rail_sets;
  std::vector<double> vent_line_y;  ///< y of the ventilation lines [m]
  std::vector<double> plant_row_y;  ///< y of the plant rows [m]
  double rear_wall_x = 0.0, end_wall_x = 0.0, side_wall_y[2] = {0, 0};
  double headland_slope_rad = 0.0;  ///< the headland floor rises towards -x: z = -x tan(slope) for x < edge_x
  std::vector<GreenhouseObstacle> obstacles;
  std::vector<Eigen::Vector3d> bumps;  ///< top of each headland bump (x, y, z) [m]

  /// Height of the floor at (x, y) without the bumps [m]: the rows' ground past the edge, the headland before it.
  double floorHeightAt(double x, double y) const;
};

/// Builds the greenhouse. Throws std::invalid_argument naming a bad parameter.
WorldDescription makeGreenhouseWorld(const GreenhouseParams& params, GreenhouseTruth* truth);

/// Writes the ground truth as YAML (edge line, rail set starts, gauge, pipe diameter, lines) to `path`.
/// Returns false if the file cannot be written.
bool writeGreenhouseTruth(const GreenhouseTruth& truth, const std::string& path);

}  // namespace thorvald_sim
