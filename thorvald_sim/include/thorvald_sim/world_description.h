#pragma once

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
