#pragma once

#include <random>
#include <string>
#include <vector>

#include "thorvald_sim/geom_writer.h"
#include "thorvald_sim/greenhouse_world.h"

namespace thorvald_sim {
namespace detail {

/// The seeded draws of a greenhouse's variation, in the order the generator makes them.
struct RailSetDraws {
  std::mt19937 rng;
  std::vector<double> set_dy;      ///< sideways move of each rail set [m] (0 without variation)
  std::vector<double> shortening;  ///< how much shorter each set is than rail_length [m]
};

/// A number in [0, 1) from the generator, the same on every platform (unlike std::uniform_real_distribution).
inline double unitDraw(std::mt19937& rng) { return rng() / 4294967296.0; }

/// Draws every set's move and length (all zero when the variation is off).
RailSetDraws drawRailSets(const GreenhouseParams& p);

/// One pipe of set `s` (side 0 right, 1 left) with its bent start, open joints and rusty pieces; records the start
/// offset in `s`. Pieces are named `<name>_s<k>`, rusty ones `rusty_<name>_s<k>`.
void writeVariedPipe(const GreenhouseParams& p, double centre_z, const std::string& name, int side, RailSetTruth& s,
                     RailSetDraws& d, GeomWriter& w);

/// The headland's sloped floor (if any), bumps, hoses, crates and trolleys as MJCF geoms; records them in `t`.
std::string headlandGeoms(const GreenhouseParams& p, GreenhouseTruth& t, std::mt19937& rng);

}  // namespace detail
}  // namespace thorvald_sim
