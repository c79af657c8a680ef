#pragma once

#include <string>

namespace thorvald_sim {

/// How a greenhouse departs from the drawing: bent and offset pipe ends, gaps and rust, a sloped and bumpy headland,
/// things left on the headland, rail sets of other lengths and spacings. Everything is drawn from one seed; every
/// magnitude 0 (the default) builds the ideal greenhouse, geom for geom.
struct GreenhouseVariation {
  unsigned seed = 1;
  double pipe_end_offset_m = 0.0;     ///< each pipe's start is offset sideways by up to +- this [m]
  double pipe_bend_length_m = 0.5;    ///< ... and bent back onto its line over this length [m]
  double pipe_gap_probability = 0.0;  ///< chance that a joint between two pipe pieces is open
  double pipe_gap_m = 0.01;           ///< width of an open joint [m]
  double rust_probability = 0.0;      ///< chance that a pipe piece is rusty (dark, matte: not shiny to the camera)
  double headland_slope_deg = 0.0;    ///< the headland floor rises towards the rear wall by this angle [deg]
  int headland_bumps = 0;             ///< low round bumps on the headland floor
  double bump_slope_deg = 1.0;        ///< steepest flank of a bump [deg]
  int hoses = 0;                      ///< hoses lying across the headland (wheels drive over them)
  int crates = 0;                     ///< crates stacked along the rear wall
  int trolleys = 0;                   ///< trolleys parked on the headland in front of plant rows
  double trolley_x_m = -0.9;          ///< centre of a parked trolley along x (the headland is x < 0) [m]
  double rail_length_jitter_m = 0.0;  ///< each rail set is up to this much shorter than rail_length [m]
  double set_spacing_jitter_m = 0.0;  ///< each rail set is moved sideways by up to +- this [m]

  /// True if anything differs from the ideal greenhouse.
  bool active() const;
  /// Throws std::invalid_argument naming the first bad key (as `variation/<key>`).
  void validate() const;
};

/// The profiles a launch names: "none" (all off), "pipes" (the pipes of "harsh" alone: +-2 cm bent ends, open
/// joints, rust; headland and rail sets as drawn) and "harsh" (every variation at the realism issue's magnitudes:
/// +-2 cm pipe ends, gaps, rust, up to 2 deg of slope and bumps, hoses, crates, trolleys, other lengths and
/// spacings). Throws std::invalid_argument for another name.
GreenhouseVariation greenhouseVariationProfile(const std::string& name);

}  // namespace thorvald_sim
