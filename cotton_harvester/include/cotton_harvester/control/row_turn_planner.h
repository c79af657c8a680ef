#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "cotton_harvester/control/waypoint_path.h"

namespace cotton_harvester {
namespace control {

/// How the rover gets from the end of one row onto the headland and into another.
enum class TurnShape {
  kU,      ///< quarter arc, straight across, quarter arc: when the rows are at least two turning radii apart
  kOmega,  ///< a bulb: a short arc away from the next row, a long arc around, an arc back into it (rows closer)
};

/// The headland turn's geometry. The rover's smallest turning radius (minTurnRadius: 2.20 m at the full 45 deg)
/// is more than the rows' 91.44 cm spacing, so a turn into the next row is an omega; a U turn needs the row
/// ceil(2 R / spacing) over (rowsOverForUTurn).
struct RowTurnParams {
  double turn_radius_m = 2.5;    ///< radius the turn's arcs are planned with (>= the rover's smallest) [m]
  double straight_m = 0.5;       ///< straight past the row's end before turning, and aligned with the next row
                                 ///< before its end [m]
  double waypoint_step_m = 0.1;  ///< spacing of the arcs' waypoints [m]

  /// Empty when sound, otherwise "key: expected ...".
  std::string check() const;
};

/// A planned turn: waypoints from the end of one row to the end of the next one (where that row starts), and the
/// room it needs in the frame of the row it leaves (x along the row's direction from its end, y to the left).
struct RowTurn {
  TurnShape shape = TurnShape::kOmega;
  std::vector<Eigen::Vector2d> waypoints;  ///< world frame [m]
  double depth_m = 0.0;                    ///< how far past the row's end it goes [m]
  double min_lateral_m = 0.0;              ///< rightmost point, from the row it leaves [m]
  double max_lateral_m = 0.0;              ///< leftmost point [m]
};

/// Smallest n such that a U turn fits from one row into the row n over: n * spacing >= 2 R.
int rowsOverForUTurn(double row_spacing_m, double turn_radius_m);

/// The turn from a row's end (`from`, the rover heading `heading_rad` out of the row) into the row that runs
/// parallel at `lateral_m` (positive: to the left), which the rover then drives in the opposite direction. A U turn
/// when |lateral_m| >= 2 R, an omega otherwise. Throws std::invalid_argument on bad parameters or lateral_m == 0.
RowTurn planRowTurn(const Eigen::Vector2d& from, double heading_rad, double lateral_m, const RowTurnParams& params);

}  // namespace control
}  // namespace cotton_harvester
