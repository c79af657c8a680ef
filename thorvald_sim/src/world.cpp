#include "thorvald_sim/world_description.h"

#include <sstream>

#include "thorvald_sim/geom_writer.h"
#include "world_checks.h"

namespace thorvald_sim {

using detail::requirePositive;

WorldDescription makeFlatWorld(double half_size_m) {
  requirePositive(half_size_m, "half_size");
  GeomWriter w;
  w.plane("floor", {0, 0, 0}, half_size_m, colours::kConcrete);
  return {"flat", w.str(), 0.0};
}

}  // namespace thorvald_sim
