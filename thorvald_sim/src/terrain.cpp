#include "thorvald_sim/terrain.h"

#include <cmath>
#include <random>
#include <sstream>

namespace thorvald_sim {

const char* groundName(Ground g) {
  switch (g) {
    case Ground::kWetConcrete:
      return "wet_concrete";
    case Ground::kLooseSoil:
      return "loose_soil";
    case Ground::kDryConcrete:
      break;
  }
  return "dry_concrete";
}

std::optional<Ground> groundFromName(const std::string& name) {
  if (name == "dry_concrete") return Ground::kDryConcrete;
  if (name == "wet_concrete") return Ground::kWetConcrete;
  if (name == "loose_soil") return Ground::kLooseSoil;
  return std::nullopt;
}

GroundContact groundContact(Ground g) {
  GroundContact c;
  switch (g) {
    case Ground::kDryConcrete:  // the scene's contact before surfaces (mu 1.0; Noon 1994 gives 0.75 sliding)
      break;
    case Ground::kWetConcrete:  // Noon (1994): wet concrete 0.60; the contact stays as stiff as concrete
      c.friction = 0.6;
      break;
    case Ground::kLooseSoil:
      // Traction on loose soil: between Noon's gravel/dirt road (0.35) and loose moist dirt (0.60-0.65); 0.45
      // (uncertain). A soft contact (time constant 0.1 s, wide impedance) lets the wheel sink a few cm and creep.
      c.friction = 0.45;
      c.solref_timeconst_s = 0.1;
      c.solimp_dmin = 0.5;
      c.solimp_width_m = 0.05;
      break;
  }
  return c;
}

Ground groundOfWorld(const std::string& world_name, Realism realism) {
  if (realism == Realism::kIdeal) return Ground::kDryConcrete;
  if (world_name.rfind("greenhouse", 0) == 0) return Ground::kWetConcrete;
  if (world_name.rfind("cotton", 0) == 0) return Ground::kLooseSoil;
  return Ground::kDryConcrete;
}

std::string bumpGeom(const std::string& name, double x, double y, double height_m, double radius_m) {
  std::ostringstream g;
  g.precision(9);
  g << "<geom name=\"" << name << "\" type=\"ellipsoid\" pos=\"" << x << " " << y << " 0\" size=\"" << radius_m << " "
    << radius_m << " " << height_m << "\" rgba=\"" << colours::kConcrete << "\"/>\n";
  return g.str();
}

WorldDescription withBumps(WorldDescription world, const BumpOptions& o) {
  std::mt19937 rng(o.seed);
  std::uniform_real_distribution<double> pos(-o.area_half_m, o.area_half_m), height(0.5, 1.0);
  std::ostringstream geoms;
  int placed = 0;
  for (int tries = 0; placed < o.count && tries < 20 * o.count; ++tries) {
    const double x = pos(rng), y = pos(rng), h = height(rng) * o.amplitude_m;
    if (std::hypot(x, y) < o.clear_radius_m + o.radius_m) continue;
    geoms << bumpGeom("bump" + std::to_string(placed++), x, y, h, o.radius_m);
  }
  world.worldbody += geoms.str();
  world.name += "_bumps";
  return world;
}

}  // namespace thorvald_sim
