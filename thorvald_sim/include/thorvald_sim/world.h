#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace thorvald_sim {

/// A world as MJCF fragments that go into the combined scene. World frame: z up, gravity -z.
struct WorldDescription {
  std::string name;
  std::string worldbody;  ///< children of <worldbody> (static geoms)
  double spawn_z = 0.0;   ///< height of the floor at the origin [m]; robots spawn relative to it
};

/// A large flat floor at z = 0.
WorldDescription makeFlatWorld(double half_size_m = 100.0);

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
  int vent_every = 2;           ///< a ventilation/heating line under every n-th plant row (0: none)
  double vent_height_m = 0.45;  ///< centre height of the ventilation lines [m]
  double vent_diameter_m = 0.3;
  double wall_margin_m = 1.2;  ///< from the outer rail sets' centres to the side walls [m]
  double wall_height_m = 3.0;
};

/// Where a rail set starts: its frame (between the pipes, at their start, x along the rails).
struct RailSetTruth {
  int index = 0;
  double start_x = 0, start_y = 0;  ///< [m]
  double yaw = 0;                   ///< [rad]
  double pipe_y[2] = {0, 0};        ///< centre lines of the two pipes [m]
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
};

/// Builds the greenhouse. Throws std::invalid_argument naming a bad parameter.
WorldDescription makeGreenhouseWorld(const GreenhouseParams& params, GreenhouseTruth* truth);

/// Writes the ground truth as YAML (edge line, rail set starts, gauge, pipe diameter, lines) to `path`.
/// Returns false if the file cannot be written.
bool writeGreenhouseTruth(const GreenhouseTruth& truth, const std::string& path);

/// The cotton paper's potted test row: plants `plant_spacing_m` apart along x from `first_plant_x_m`, on a
/// ground that rises along +x by `slope_deg` (0.25 and 2.77 in its two tests).
struct CottonRowParams {
  int plants = 10;
  double plant_spacing_m = 0.30;
  double first_plant_x_m = 1.5;
  double row_y_m = 0.0;
  double plant_height_m = 0.8;
  int bolls_per_plant = 3;
  double boll_radius_m = 0.035;
  double slope_deg = 0.0;
  unsigned seed = 1;                   ///< places the bolls and leaves
  int leaves_per_plant = 4;            ///< leaves spread over the stem (potted tests: defoliated, few)
  double leaf_over_boll_fraction = 0;  ///< share of bolls with a leaf just above them, partly hiding them from above
};

struct CottonRowTruth {
  CottonRowParams params;
  std::vector<Eigen::Vector3d> plant_bases;  ///< world position of each plant's stem foot [m]
  std::vector<Eigen::Vector3d> bolls;        ///< world centre of each boll [m]
  std::vector<int> boll_plant;               ///< which plant each boll grows on
};

/// Builds the cotton row. Throws std::invalid_argument naming a bad parameter.
WorldDescription makeCottonRowWorld(const CottonRowParams& params, CottonRowTruth* truth);

/// Writes the cotton row's ground truth (plants, bolls) as YAML. Returns false if the file cannot be written.
bool writeCottonRowTruth(const CottonRowTruth& truth, const std::string& path);

/// Colours [r g b a] the worlds use, so tests and perception know what to expect.
namespace colours {
constexpr const char* kConcrete = "0.62 0.62 0.6 1";
constexpr const char* kSoil = "0.35 0.26 0.18 1";
constexpr const char* kPipe = "0.8 0.8 0.82 1";
constexpr const char* kSupport = "0.3 0.3 0.3 1";
constexpr const char* kPlant = "0.15 0.55 0.15 1";
constexpr const char* kLeaf = "0.2 0.6 0.15 1";
constexpr const char* kStem = "0.35 0.45 0.15 1";
constexpr const char* kPot = "0.45 0.25 0.12 1";
constexpr const char* kBoll = "1 1 1 1";
constexpr const char* kWall = "0.85 0.85 0.8 1";
constexpr const char* kVent = "0.75 0.75 0.7 1";
}  // namespace colours

}  // namespace thorvald_sim
