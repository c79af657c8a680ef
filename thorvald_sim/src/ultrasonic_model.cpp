#include "thorvald_sim/ultrasonic_model.h"

#include <algorithm>
#include <limits>

namespace thorvald_sim {

double nearestEcho(const std::vector<EchoRay>& rays, const UltrasonicModel& model) {
  double best = std::numeric_limits<double>::infinity();
  for (const EchoRay& r : rays)
    if (r.range_m >= 0.0 && r.incidence_rad <= model.max_incidence_rad) best = std::min(best, r.range_m);
  return best;
}

double crossTalk(double own_m, double other_path_m, double probability, std::mt19937& rng) {
  if (probability <= 0.0 || !(other_path_m >= 0.0)) return own_m;
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  return uni(rng) < probability ? std::min(own_m, 0.5 * other_path_m) : own_m;
}

}  // namespace thorvald_sim
