#pragma once

// The ground the wheels drive on: the contact of a wheel per surface (friction and softness) and uneven ground
// (seeded bumps on a flat world). README "Wheels and ground".

#include <optional>
#include <string>

#include "thorvald_sim/realism.h"
#include "thorvald_sim/world_description.h"

namespace thorvald_sim {

enum class Ground { kDryConcrete, kWetConcrete, kLooseSoil };

/// "dry_concrete", "wet_concrete", "loose_soil".
const char* groundName(Ground g);
/// The surface named `name`, or nothing for an unknown name.
std::optional<Ground> groundFromName(const std::string& name);

/// How a wheel touches a surface in MuJoCo: Coulomb friction of the tyre and the contact's softness (solref time
/// constant and damping ratio, solimp impedance). A softer contact lets the wheel sink and creep (slip) under
/// traction, as in loose soil.
struct GroundContact {
  double friction = 1.0;             ///< sliding friction coefficient tyre-surface
  double solref_timeconst_s = 0.02;  ///< MuJoCo's default contact stiffness
  double solref_dampratio = 1.0;
  double solimp_dmin = 0.9, solimp_dmax = 0.95, solimp_width_m = 0.001;  ///< MuJoCo's defaults
};

/// The contact values of a surface (sources in the README). Dry concrete is the scene's contact before surfaces
/// existed, so a scene on it is byte-identical to one without a surface.
GroundContact groundContact(Ground g);

/// The surface a world's floor has in a realism profile: `ideal` is dry concrete everywhere (the simulator as it
/// was); `datasheet` makes the greenhouse floor wet concrete (watered crops) and the cotton field loose soil.
/// Worlds are told apart by WorldDescription::name ("greenhouse...", "cotton...").
Ground groundOfWorld(const std::string& world_name, Realism realism);

/// Seeded bumps on the ground: half-ellipsoids of height `amplitude_m` (each drawn uniformly between half and the
/// full amplitude) and footprint radius `radius_m`, scattered over a square of half size `area_half_m` around the
/// origin, `count` of them. Static geoms of the world; robots spawn over a bump-free circle of `clear_radius_m`.
struct BumpOptions {
  double amplitude_m = 0.05;
  double radius_m = 0.4;
  double area_half_m = 12.0;
  int count = 150;
  double clear_radius_m = 1.5;
  unsigned seed = 1;
};

/// `world` with the bumps added to its worldbody.
WorldDescription withBumps(WorldDescription world, const BumpOptions& options);

/// One bump (a half-ellipsoid geom named `name`) centred at (x, y) on the floor at z = 0.
std::string bumpGeom(const std::string& name, double x, double y, double height_m, double radius_m);

}  // namespace thorvald_sim
