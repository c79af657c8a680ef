#include "thorvald_sim/cotton_world.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>
#include <regex>
#include <sstream>
#include <stdexcept>

#include "thorvald_sim/geom_writer.h"
#include "world_checks.h"

namespace thorvald_sim {

using detail::requirePositive;

namespace {

/// Stems and branches: stiff contacts, so that a pushing body stops at them instead of sinking through.
constexpr const char* kStiff = " solref=\"0.004 1\" solimp=\"0.95 0.99 0.001\"";

std::string vec(const Eigen::Vector3d& v) {
  std::ostringstream s;
  s.precision(7);
  s << v.x() << " " << v.y() << " " << v.z();
  return s.str();
}

std::string quat(const Eigen::Quaterniond& q) {
  std::ostringstream s;
  s.precision(7);
  s << q.w() << " " << q.x() << " " << q.y() << " " << q.z();
  return s.str();
}

Eigen::Quaterniond yawPitch(double yaw, double pitch) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                            Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()));
}

/// A colour "r g b 1" scaled by `shade` (clamped to 1).
std::string rgba(double r, double g, double b, double shade = 1.0) {
  std::ostringstream s;
  s.precision(4);
  s << std::min(1.0, r * shade) << " " << std::min(1.0, g * shade) << " " << std::min(1.0, b * shade) << " 1";
  return s.str();
}

/// Writes the datasheet row's bodies and geoms (MJCF lines of the world body).
class DatasheetRowWriter {
 public:
  DatasheetRowWriter(const CottonRowParams& p, double slope_rad) : p_(p), r_(p.realism), th_(slope_rad), rng_(p.seed) {
    x_.precision(7);
  }

  Eigen::Vector3d ground(double x, double y) const { return {x, y, x * std::tan(th_)}; }
  double u() { return uni_(rng_); }

  /// A geom line: `attrs` carries type, size, position and orientation.
  void geom(const std::string& name, const std::string& attrs, const std::string& colour, int contype, int conaffinity,
            double mass = 0.0, const char* extra = "") {
    x_ << "<geom name=\"" << name << "\" " << attrs << " rgba=\"" << colour << "\" contype=\"" << contype
       << "\" conaffinity=\"" << conaffinity << "\"";
    if (mass > 0.0) x_ << " mass=\"" << mass << "\"";
    x_ << extra << "/>\n";
  }

  /// Soil clods and weeds along the row, on the ground (visual only). They sit on a static body of their own, not on
  /// the world body: MuJoCo pairs every geom of two bodies whose boxes overlap before it looks at contype, and the
  /// world body's box (its ground plane) overlaps every boll and leaf, while this body's box stays low.
  void soil(double x0, double x1) {
    x_ << "<body name=\"clods_and_weeds\">\n";
    for (int k = 0; k < r_.clods; ++k) {
      const Eigen::Vector3d c = ground(x0 + (x1 - x0) * u(), (2.0 * u() - 1.0) * 0.7);
      const double s = 0.015 + 0.035 * u(), shade = 0.6 + 0.5 * u();
      geom("clod" + std::to_string(k),
           "type=\"ellipsoid\" size=\"" + vec({s, s * (0.6 + 0.4 * u()), 0.4 * s}) + "\" pos=\"" + vec(c) +
               "\" quat=\"" + quat(yawPitch(2 * M_PI * u(), 0.0)) + "\"",
           rgba(0.35, 0.26, 0.18, shade), 0, 0);
    }
    for (int k = 0; k < r_.weeds; ++k) {
      const Eigen::Vector3d c = ground(x0 + (x1 - x0) * u(), (2.0 * u() - 1.0) * 0.6);
      for (int l = 0; l < 3; ++l) {
        const double a = 2 * M_PI * (l + u()) / 3.0;
        geom("weed" + std::to_string(k) + "_" + std::to_string(l),
             "type=\"ellipsoid\" size=\"0.03 0.012 0.003\" pos=\"" +
                 vec(c + Eigen::Vector3d(0.025 * std::cos(a), 0.025 * std::sin(a), 0.01)) + "\" quat=\"" +
                 quat(yawPitch(a, -0.3)) + "\"",
             rgba(0.25, 0.55, 0.15, 0.7 + 0.4 * u()), 0, 0);
      }
    }
    x_ << "</body>\n";
  }

  /// A springy leaf: a body at its stalk on two hinges (up-down and sideways) with stiffness and damping, the blade
  /// reaching `reach` out along `yaw` from the stalk.
  void leaf(const std::string& name, const Eigen::Vector3d& stalk, double yaw, const Eigen::Vector3d& half,
            double reach) {
    x_ << "<body name=\"" << name << "\" pos=\"" << vec(stalk) << "\" quat=\"" << quat(yawPitch(yaw, 0.0)) << "\">\n";
    for (const char* axis : {"pitch", "swing"}) {
      x_ << " <joint name=\"" << name << "_" << axis << "\" type=\"hinge\" axis=\""
         << (axis[0] == 'p' ? "0 1 0" : "0 0 1") << "\" stiffness=\"" << r_.leaf_stiffness << "\" damping=\""
         << r_.leaf_damping << "\" armature=\"0.0001\" range=\"-1.4 1.4\" limited=\"true\"/>\n";
    }
    geom(name, "type=\"ellipsoid\" size=\"" + vec(half) + "\" pos=\"" + vec({reach, 0, 0}) + "\"",
         rgba(0.2, 0.6, 0.15, 0.8 + 0.35 * u()), kPlantContype, 0, 0.002);
    x_ << "</body>\n";
  }

  /// A boll: lobes (white, slightly cream) around its centre and bracts below, on three spring joints that break.
  void boll(const std::string& name, const Eigen::Vector3d& c, bool half_open) {
    const double br = p_.boll_radius_m, k = r_.boll_stiffness;
    x_ << "<body name=\"" << name << "\" pos=\"" << vec(c) << "\">\n";
    const char* axes[3] = {"1 0 0", "0 1 0", "0 0 1"};
    for (int a = 0; a < 3; ++a)
      x_ << " <joint name=\"" << name << "_"
         << "xyz"[a] << "\" type=\"slide\" axis=\"" << axes[a] << "\" stiffness=\"" << k
         << "\" damping=\"2\" armature=\"0.005\"/>\n";
    const double lobe_r = (half_open ? 0.35 : 0.55) * br, ring = (half_open ? 0.3 : 0.45) * br;
    auto cream = [&]() { return 0.9 + 0.1 * u(); };
    const double core_cream = cream();
    geom(name, "type=\"sphere\" size=\"" + std::to_string((half_open ? 0.4 : 0.6) * br) + "\"",
         rgba(1.0, 0.99 * core_cream + 0.01, 0.96 * core_cream + 0.02), kBollContype, 1, 0.004);
    const double turn = 2 * M_PI * u();
    for (int l = 0; l < r_.lobes; ++l) {
      const double a = turn + 2 * M_PI * l / r_.lobes, cr = cream();
      const Eigen::Vector3d at(ring * std::cos(a), ring * std::sin(a), 0.15 * br * (u() - 0.3));
      geom(name + "_lobe" + std::to_string(l),
           "type=\"ellipsoid\" size=\"" + vec({lobe_r, 0.85 * lobe_r, 0.9 * lobe_r}) + "\" pos=\"" + vec(at) +
               "\" quat=\"" + quat(yawPitch(a, 0.0)) + "\"",
           rgba(1.0, 0.98 * cr + 0.02, 0.93 * cr + 0.05), kBollContype, 1, 0.002);
    }
    // Bracts: dry pointed pieces under the boll (dark brown); a half-open boll's larger ones (green-brown) rise
    // around its white core.
    const int bracts = r_.lobes;
    for (int b = 0; b < bracts; ++b) {
      const double a = turn + 2 * M_PI * (b + 0.5) / bracts;
      const double len = (half_open ? 0.75 : 0.6) * br, tilt = half_open ? -1.0 : 0.55;
      const Eigen::Vector3d at((half_open ? 0.55 : 0.6) * br * std::cos(a), (half_open ? 0.55 : 0.6) * br * std::sin(a),
                               (half_open ? -0.05 : -0.45) * br);
      geom(name + "_bract" + std::to_string(b),
           "type=\"ellipsoid\" size=\"" + vec({len, 0.3 * len, 0.06 * len}) + "\" pos=\"" + vec(at) + "\" quat=\"" +
               quat(yawPitch(a, tilt)) + "\"",
           half_open ? rgba(0.38, 0.36, 0.14, 0.8 + 0.3 * u()) : rgba(0.3, 0.2, 0.1, 0.7 + 0.4 * u()), kBollContype, 1,
           0.0005);
    }
    x_ << "</body>\n";
  }

  /// Static dry leaves and empty burrs (brown, visual only), on a static body of the plant's own (as soil()).
  void dryParts(const std::string& n, const Eigen::Vector3d& base, double height) {
    x_ << "<body name=\"" << n << "_dry_parts\">\n";
    for (int k = 0; k < r_.dry_leaves_per_plant; ++k) {
      const double a = 2 * M_PI * u(), h = (0.3 + 0.5 * u()) * height;
      geom(n + "_dry" + std::to_string(k),
           "type=\"ellipsoid\" size=\"0.045 0.03 0.006\" pos=\"" +
               vec(base + Eigen::Vector3d(0.06 * std::cos(a), 0.06 * std::sin(a), h)) + "\" quat=\"" +
               quat(yawPitch(a, 0.5 * u())) + "\"",
           rgba(0.45, 0.32, 0.17, 0.7 + 0.4 * u()), 0, 0);
    }
    for (int k = 0; k < r_.burrs_per_plant; ++k) {
      const double a = 2 * M_PI * u(), h = (0.4 + 0.5 * u()) * height, rad = 0.05 + 0.06 * u();
      const Eigen::Vector3d c = base + Eigen::Vector3d(rad * std::cos(a), rad * std::sin(a), h);
      for (int l = 0; l < 4; ++l) {
        const double b = 2 * M_PI * (l + 0.5 * u()) / 4.0;
        geom(n + "_burr" + std::to_string(k) + "_" + std::to_string(l),
             "type=\"ellipsoid\" size=\"0.022 0.012 0.004\" pos=\"" +
                 vec(c + Eigen::Vector3d(0.015 * std::cos(b), 0.015 * std::sin(b), 0.0)) + "\" quat=\"" +
                 quat(yawPitch(b, -0.7)) + "\"",
             rgba(0.33, 0.22, 0.12, 0.7 + 0.4 * u()), 0, 0);
      }
    }
    x_ << "</body>\n";
  }

  void plant(int i, CottonRowTruth* t);

  std::string str() const { return x_.str(); }

 private:
  const CottonRowParams& p_;
  const CottonPlantRealism& r_;
  const double th_;
  std::mt19937 rng_;
  std::uniform_real_distribution<double> uni_{0.0, 1.0};
  std::ostringstream x_;
};

void DatasheetRowWriter::plant(int i, CottonRowTruth* t) {
  const std::string n = "plant" + std::to_string(i);
  const Eigen::Vector3d base = ground(p_.first_plant_x_m + i * p_.plant_spacing_m, p_.row_y_m);
  const double height = p_.plant_height_m * (1.0 + r_.height_spread * (2.0 * u() - 1.0));
  t->plant_bases.push_back(base);
  geom(n + "_pot", "type=\"cylinder\" size=\"0.1 0.11\" pos=\"" + vec(base + Eigen::Vector3d(0, 0, 0.1)) + "\"",
       colours::kPot, 1, 3);
  const Eigen::Vector3d top = base + Eigen::Vector3d(0, 0, height);
  geom(n + "_stem",
       "type=\"capsule\" size=\"0.008\" fromto=\"" + vec(base + Eigen::Vector3d(0, 0, 0.2)) + " " + vec(top) + "\"",
       rgba(0.4, 0.42, 0.18, 0.8 + 0.3 * u()), kStemContype, 0, 0.0, kStiff);
  for (int l = 0; l < p_.leaves_per_plant; ++l) {
    const double a = 2 * M_PI * u(), h = std::min(0.35 + 0.4 * u() * height, height);
    leaf(n + "_leaf" + std::to_string(l), base + Eigen::Vector3d(0.0, 0.0, h), a, {0.06, 0.05, 0.012}, 0.07);
  }
  for (int b = 0; b < p_.bolls_per_plant; ++b) {
    const double a = 2 * M_PI * (b + 0.6 * u()) / std::max(1, p_.bolls_per_plant);
    const double rad = 0.06 + 0.08 * u(), h = (0.45 + 0.5 * u()) * height;
    const Eigen::Vector3d c = base + Eigen::Vector3d(rad * std::cos(a), rad * std::sin(a), h);
    const std::string bn = n + "_boll" + std::to_string(b);
    const bool half_open = u() < r_.half_open_fraction;
    // The branch from the stem to the boll's foot: rigid, the arm cannot push through it.
    const Eigen::Vector3d foot = c - Eigen::Vector3d(0, 0, 0.9 * p_.boll_radius_m);
    geom(bn + "_branch",
         "type=\"capsule\" size=\"0.004\" fromto=\"" + vec(base + Eigen::Vector3d(0, 0, h - 0.06)) + " " + vec(foot) +
             "\"",
         rgba(0.4, 0.42, 0.18), kStemContype, 0, 0.0, kStiff);
    boll(bn, c, half_open);
    if (p_.leaf_over_boll_fraction > 0.0 && u() < p_.leaf_over_boll_fraction) {
      const double la = 2 * M_PI * u(), shift = p_.boll_radius_m * u();
      const Eigen::Vector3d blade =
          c + Eigen::Vector3d(shift * std::cos(la), shift * std::sin(la), p_.boll_radius_m + 0.02);
      const Eigen::Vector3d stalk = blade - 0.06 * Eigen::Vector3d(std::cos(la), std::sin(la), 0.0);
      leaf(bn + "_leaf", stalk, la, {0.06, 0.045, 0.008}, 0.06);
    }
    t->bolls.push_back(c);
    t->boll_plant.push_back(i);
    t->boll_half_open.push_back(half_open ? 1 : 0);
  }
  dryParts(n, base, height);
}

WorldDescription makeDatasheetRow(const CottonRowParams& p, CottonRowTruth* truth) {
  const CottonPlantRealism& r = p.realism;
  if (r.lobes < 4 || r.lobes > 5) throw std::invalid_argument("realism.lobes must be 4 or 5");
  if (!(r.half_open_fraction >= 0.0 && r.half_open_fraction <= 1.0))
    throw std::invalid_argument("realism.half_open_fraction must be within 0..1");
  if (!(r.height_spread >= 0.0 && r.height_spread < 0.5))
    throw std::invalid_argument("realism.height_spread must be within 0..0.5");
  if (r.dry_leaves_per_plant < 0 || r.burrs_per_plant < 0 || r.clods < 0 || r.weeds < 0)
    throw std::invalid_argument("realism: dry leaves, burrs, clods and weeds must not be negative");
  requirePositive(r.leaf_stiffness, "realism.leaf_stiffness");
  requirePositive(r.boll_stiffness, "realism.boll_stiffness");
  requirePositive(r.boll_break_force, "realism.boll_break_force");
  if (!(r.leaf_damping >= 0.0)) throw std::invalid_argument("realism.leaf_damping must not be negative");
  CottonRowTruth t;
  t.params = p;
  const double th = p.slope_deg * M_PI / 180.0;
  GeomWriter w;
  w.tiltedPlane("ground", {0, 0, 0}, 200.0, -th, colours::kSoil);
  DatasheetRowWriter d(p, th);
  for (int i = 0; i < p.plants; ++i) d.plant(i, &t);
  d.soil(p.first_plant_x_m - 3.0, p.first_plant_x_m + p.plants * p.plant_spacing_m + 2.0);
  if (truth) *truth = t;
  return {"cotton_row", w.str() + d.str(), 0.0};
}

}  // namespace

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
  if (p.datasheet) return makeDatasheetRow(p, truth);
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
