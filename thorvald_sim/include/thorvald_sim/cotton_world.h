#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "thorvald_sim/world_description.h"

namespace thorvald_sim {

/// The `datasheet` plants of the cotton row (CottonRowParams::datasheet): what a real plant has and the flat one
/// of `ideal` lacks. Forces [N], stiffnesses [N/m or N m/rad], lengths [m].
struct CottonPlantRealism {
  int lobes = 5;                     ///< locks of an open boll: spheres around its centre (4 or 5)
  double half_open_fraction = 0.25;  ///< share of bolls half open: smaller white lobes inside larger bracts
  double height_spread = 0.15;       ///< plants' heights vary uniformly by +- this share
  int dry_leaves_per_plant = 2;      ///< brown dry leaves on the stem
  int burrs_per_plant = 1;           ///< empty brown burrs (picked or shed bolls' husks)
  int clods = 120;                   ///< soil clods along the row (visual: the wheels roll over the plane)
  int weeds = 24;                    ///< small weeds between the plants
  double leaf_stiffness = 0.04;      ///< a leaf's hinge springs [N m/rad] ...
  double leaf_damping = 0.002;       ///< ... and their damping [N m s/rad]
  double boll_stiffness = 300.0;     ///< a boll held on its branch by springs in x, y, z [N/m] ...
  double boll_break_force = 4.0;     ///< ... breaks off when their force exceeds this [N]
};

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
  /// false (`ideal`): flat-coloured spheres, ellipsoids and capsules fixed to the world, as ever. true
  /// (`datasheet`): lobed bolls with bracts on spring joints that break, springy leaves on hinges, rigid stems and
  /// branches, dry leaves, burrs, clods, weeds and plants of different heights (writeDatasheetPlant). Collision
  /// classes: stems and branches contype kStemContype; leaves kPlantContype; bolls kBollContype (they also meet
  /// the ground); give a body that should push plants conaffinity kStemContype | kPlantContype | kBollContype.
  bool datasheet = false;
  CottonPlantRealism realism;
};

/// Tessellation of curved geoms (MuJoCo's numslices; numstacks half of it) for cameras over the datasheet row: its
/// lobed bolls, bracts and burrs are spheres a few pixels across in a 720p frame from 2 m, so 16 slices put a
/// silhouette within r (1 - cos(pi / 16)) = 2 % of r of the exact one (0.1 px for a 1.5 cm lobe) while drawing a
/// quarter of the triangles of 32 (CameraRenderer refines the depth of curved geoms on their exact surface anyway).
constexpr int kDatasheetRowRenderSlices = 16;

/// Collision bits of the datasheet plants (CottonRowParams::datasheet): leaves, stems and branches, bolls.
constexpr int kPlantContype = 8;
constexpr int kStemContype = 16;
constexpr int kBollContype = 32;

struct CottonRowTruth {
  CottonRowParams params;
  std::vector<Eigen::Vector3d> plant_bases;  ///< world position of each plant's stem foot [m]
  std::vector<Eigen::Vector3d> bolls;        ///< world centre of each boll [m]
  std::vector<int> boll_plant;               ///< which plant each boll grows on
  std::vector<char> boll_half_open;          ///< datasheet: the boll is half open (empty in ideal)
};

/// Builds the cotton row. Throws std::invalid_argument naming a bad parameter.
WorldDescription makeCottonRowWorld(const CottonRowParams& params, CottonRowTruth* truth);

/// Writes the cotton row's ground truth (plants, bolls) as YAML. Returns false if the file cannot be written.
bool writeCottonRowTruth(const CottonRowTruth& truth, const std::string& path);

}  // namespace thorvald_sim

namespace thorvald_sim {

/// A field of cotton (the paper's field: rows 91.44 cm apart): `rows` rows along +x, each `row_length_m` long from
/// `row.first_plant_x_m`, row k at y = row.row_y_m + k * row_spacing_m (to the left of the first). Every row is a
/// makeCottonRowWorld row of `row` (its own seed: row.seed + k); plants are numbered through the field (plant<i>_...).
struct CottonFieldParams {
  int rows = 4;
  double row_spacing_m = 0.9144;  ///< 36 in (paper §2.13)
  double row_length_m = 20.0;     ///< first to last plant of a row [m]
  CottonRowParams row;            ///< plants, bolls, leaves, slope and profile of each row (plants: from the length)
  /// false: the ideal plants do not collide with anything (the rover's wheels, which run on the neighbouring rows'
  /// lines at this spacing, pass through them); true: as makeCottonRowWorld makes them. Datasheet plants keep their
  /// own collision classes either way.
  bool plants_collide = false;
};

/// The field's ground truth and the rows' ends as a user records them with the GNSS (world frame).
struct CottonFieldTruth {
  CottonRowTruth plants;                   ///< all rows' plants and bolls (boll_plant: the field-wide plant index)
  std::vector<int> plant_row;              ///< which row each plant is in
  std::vector<Eigen::Vector2d> row_start;  ///< each row's first plant (x, y) [m]
  std::vector<Eigen::Vector2d> row_end;    ///< and its last [m]
};

/// Builds the field. Throws std::invalid_argument naming a bad parameter.
WorldDescription makeCottonFieldWorld(const CottonFieldParams& params, CottonFieldTruth* truth);

/// Writes the rows' end waypoints as YAML (`rows: [{row: k, start: [x, y], end: [x, y]}, ...]`, world frame, metres).
/// Returns false if the file cannot be written.
bool writeCottonFieldWaypoints(const CottonFieldTruth& truth, const std::string& path);

}  // namespace thorvald_sim
