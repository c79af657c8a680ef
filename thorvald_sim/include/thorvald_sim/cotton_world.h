#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "thorvald_sim/world_description.h"

namespace thorvald_sim {

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

}  // namespace thorvald_sim
