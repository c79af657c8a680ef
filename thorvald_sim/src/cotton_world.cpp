#include "thorvald_sim/cotton_world.h"

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>

#include "thorvald_sim/geom_writer.h"
#include "world_checks.h"

namespace thorvald_sim {

using detail::requirePositive;

WorldDescription makeCottonRowWorld(const CottonRowParams& p, CottonRowTruth* truth) {
  if (p.plants < 1) throw std::invalid_argument("plants must be at least 1");
  requirePositive(p.plant_spacing_m, "plant_spacing");
  requirePositive(p.plant_height_m, "plant_height");
  requirePositive(p.boll_radius_m, "boll_radius");
  if (p.bolls_per_plant < 0) throw std::invalid_argument("bolls_per_plant must not be negative");
  if (!(std::fabs(p.slope_deg) < 30.0)) throw std::invalid_argument("slope_deg must be within +-30 degrees");
  if (p.leaves_per_plant < 0 || p.leaves_per_plant > 200)
    throw std::invalid_argument("leaves_per_plant must be within 0..200");
  if (!(p.leaf_over_boll_fraction >= 0.0 && p.leaf_over_boll_fraction <= 1.0))
    throw std::invalid_argument("leaf_over_boll_fraction must be within 0..1");
  CottonRowTruth t;
  t.params = p;
  const double th = p.slope_deg * M_PI / 180.0;
  // Ground rises along +x: a point (x, y) of the ground plane sits at height x tan(th).
  auto ground = [&](double x, double y) { return Eigen::Vector3d(x, y, x * std::tan(th)); };
  GeomWriter w;
  w.tiltedPlane("ground", {0, 0, 0}, 200.0, -th, colours::kSoil);
  std::mt19937 rng(p.seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < p.plants; ++i) {
    const std::string n = "plant" + std::to_string(i);
    const Eigen::Vector3d base = ground(p.first_plant_x_m + i * p.plant_spacing_m, p.row_y_m);
    t.plant_bases.push_back(base);
    w.cylinder(n + "_pot", base + Eigen::Vector3d(0, 0, 0.1), 0.1, 0.11, colours::kPot);
    const Eigen::Vector3d top = base + Eigen::Vector3d(0, 0, p.plant_height_m);
    w.capsule(n + "_stem", base + Eigen::Vector3d(0, 0, 0.2), top, 0.008, colours::kStem);
    for (int l = 0; l < p.leaves_per_plant; ++l) {
      const double a = 2 * M_PI * u(rng), h = 0.35 + 0.4 * u(rng) * p.plant_height_m;
      w.ellipsoid(n + "_leaf" + std::to_string(l),
                  base + Eigen::Vector3d(0.07 * std::cos(a), 0.07 * std::sin(a), std::min(h, p.plant_height_m)),
                  {0.06, 0.05, 0.012}, a, colours::kLeaf);
    }
    for (int b = 0; b < p.bolls_per_plant; ++b) {
      const double a = 2 * M_PI * (b + 0.6 * u(rng)) / std::max(1, p.bolls_per_plant);
      const double rad = 0.06 + 0.08 * u(rng), h = (0.45 + 0.5 * u(rng)) * p.plant_height_m;
      const Eigen::Vector3d c = base + Eigen::Vector3d(rad * std::cos(a), rad * std::sin(a), h);
      w.sphere(n + "_boll" + std::to_string(b), c, p.boll_radius_m, colours::kBoll);
      // Undefoliated plants: a leaf just above the boll, shifted by up to its radius, hides part of it from above.
      if (p.leaf_over_boll_fraction > 0.0 && u(rng) < p.leaf_over_boll_fraction) {
        const double la = 2 * M_PI * u(rng), shift = p.boll_radius_m * u(rng);
        w.ellipsoid(n + "_boll" + std::to_string(b) + "_leaf",
                    c + Eigen::Vector3d(shift * std::cos(la), shift * std::sin(la), p.boll_radius_m + 0.02),
                    {0.06, 0.045, 0.008}, la, colours::kLeaf);
      }
      t.bolls.push_back(c);
      t.boll_plant.push_back(i);
    }
  }
  if (truth) *truth = t;
  return {"cotton_row", w.str(), 0.0};
}

bool writeCottonRowTruth(const CottonRowTruth& t, const std::string& path) {
  std::ofstream out(path);
  if (!out) return false;
  out.precision(6);
  out << "# Ground truth written by thorvald_sim's cotton row generator (world frame, metres).\n"
      << "slope_deg: " << t.params.slope_deg << "\nplant_spacing: " << t.params.plant_spacing_m << "\nplants:\n";
  for (const auto& b : t.plant_bases) out << "  - [" << b.x() << ", " << b.y() << ", " << b.z() << "]\n";
  out << "bolls:\n";
  for (size_t i = 0; i < t.bolls.size(); ++i)
    out << "  - {plant: " << t.boll_plant[i] << ", x: " << t.bolls[i].x() << ", y: " << t.bolls[i].y()
        << ", z: " << t.bolls[i].z() << ", radius: " << t.params.boll_radius_m << "}\n";
  return static_cast<bool>(out);
}

}  // namespace thorvald_sim
