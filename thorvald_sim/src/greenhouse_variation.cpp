#include "thorvald_sim/greenhouse_variation.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "greenhouse_variation_geoms.h"

namespace thorvald_sim {

namespace {

constexpr double kPiece = 2.0;  ///< pipe and floor pieces, as the ideal greenhouse's [m]
constexpr const char* kCrateColour = "0.2 0.35 0.7 1";
constexpr const char* kTrolleyColour = "0.55 0.55 0.58 1";
constexpr const char* kHoseColour = "0.1 0.45 0.15 1";

void requireIn(double v, double lo, double hi, const char* key) {
  if (!(v >= lo && v <= hi))
    throw std::invalid_argument(std::string("variation/") + key + " must lie in [" + std::to_string(lo) + ", " +
                                std::to_string(hi) + "], got " + std::to_string(v));
}

/// Writes a box turned by `pitch` about y, then `yaw` about z (MJCF euler, intrinsic x-y-z).
void rotatedBox(std::ostringstream& out, const std::string& name, const Eigen::Vector3d& pos,
                const Eigen::Vector3d& half, double pitch, double yaw, const char* rgba) {
  out << "<geom name=\"" << name << "\" type=\"box\" pos=\"" << pos.x() << " " << pos.y() << " " << pos.z()
      << "\" size=\"" << half.x() << " " << half.y() << " " << half.z() << "\" euler=\"0 " << pitch << " " << yaw
      << "\" rgba=\"" << rgba << "\"/>\n";
}

/// The headland floor as slabs tilted by the slope about the edge line: z = -x tan(slope) on top.
void slopedFloor(const GreenhouseParams& p, const GreenhouseTruth& t, std::ostringstream& out) {
  const double th = t.headland_slope_rad, along = p.headland_depth_m / std::cos(th);
  const double thick = p.row_ground_drop_m + p.headland_depth_m * std::tan(th);  // reaches the rows' ground
  const int nx = std::max(1, static_cast<int>(std::ceil(along / kPiece)));
  const int ny = std::max(1, static_cast<int>(std::ceil((t.edge_y_max - t.edge_y_min) / kPiece)));
  const double lx = along / nx, ly = (t.edge_y_max - t.edge_y_min) / ny;
  int k = 0;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j, ++k) {
      const double a = -(i + 0.5) * lx, c = -0.5 * thick;  // centre in the slab's own frame
      const Eigen::Vector3d pos(t.edge_x + a * std::cos(th) + c * std::sin(th), t.edge_y_min + (j + 0.5) * ly,
                                t.floor_z - a * std::sin(th) + c * std::cos(th));
      rotatedBox(out, "headland_floor_s" + std::to_string(k), pos, {0.5 * lx, 0.5 * ly, 0.5 * thick}, th, 0.0,
                 colours::kConcrete);
    }
}

/// Low round bumps: caps of large spheres whose flanks are at most bump_slope steep.
void bumps(const GreenhouseParams& p, GreenhouseTruth& t, std::mt19937& rng, std::ostringstream& out) {
  const GreenhouseVariation& v = p.variation;
  const double a = 0.5, big_r = a / std::sin(v.bump_slope_deg * M_PI / 180.0);
  const double h = big_r - std::sqrt(big_r * big_r - a * a);
  for (int i = 0; i < v.headland_bumps; ++i) {
    const double x = -0.8 - detail::unitDraw(rng) * (p.headland_depth_m - 1.6);
    const double y = t.edge_y_min + 0.5 + detail::unitDraw(rng) * (t.edge_y_max - t.edge_y_min - 1.0);
    const double z = t.floorHeightAt(x, y) + h;
    t.bumps.emplace_back(x, y, z);
    out << "<geom name=\"headland_bump" << i << "\" type=\"sphere\" pos=\"" << x << " " << y << " " << z - big_r
        << "\" size=\"" << big_r << "\" rgba=\"" << colours::kConcrete << "\"/>\n";
  }
}

void hoses(const GreenhouseParams& p, GreenhouseTruth& t, std::mt19937& rng, std::ostringstream& out) {
  const double r = 0.012;
  for (int i = 0; i < p.variation.hoses; ++i) {
    GreenhouseObstacle o{"hose" + std::to_string(i), "hose"};
    o.x = -1.0 - detail::unitDraw(rng) * (p.headland_depth_m - 2.0);
    o.y = t.edge_y_min + 0.5 * (t.edge_y_max - t.edge_y_min) * (0.5 + detail::unitDraw(rng));
    o.yaw = M_PI / 2 + 0.6 * (detail::unitDraw(rng) - 0.5);  // across the headland
    o.half_length = 1.5 + 1.5 * detail::unitDraw(rng), o.half_width = r, o.height = 2 * r;
    const Eigen::Vector3d d(std::cos(o.yaw) * o.half_length, std::sin(o.yaw) * o.half_length, 0.0);
    const Eigen::Vector3d c(o.x, o.y, t.floorHeightAt(o.x, o.y) + r), a = c - d, b = c + d;
    out << "<geom name=\"" << o.name << "\" type=\"capsule\" fromto=\"" << a.x() << " " << a.y() << " "
        << t.floorHeightAt(a.x(), a.y()) + r << " " << b.x() << " " << b.y() << " " << t.floorHeightAt(b.x(), b.y()) + r
        << "\" size=\"" << r << "\" rgba=\"" << kHoseColour << "\"/>\n";
    t.obstacles.push_back(o);
  }
}

/// A box standing on the floor, recorded in the truth.
void standingBox(GreenhouseTruth& t, const GreenhouseObstacle& o, const char* rgba, std::ostringstream& out) {
  rotatedBox(out, o.name, {o.x, o.y, t.floorHeightAt(o.x, o.y) + 0.5 * o.height},
             {o.half_length, o.half_width, 0.5 * o.height}, 0.0, o.yaw, rgba);
  t.obstacles.push_back(o);
}

/// Crates along the rear wall and trolleys in front of plant rows (each row at most one).
void cratesAndTrolleys(const GreenhouseParams& p, GreenhouseTruth& t, std::mt19937& rng, std::ostringstream& out) {
  const GreenhouseVariation& v = p.variation;
  const double span = t.edge_y_max - t.edge_y_min - 1.0;
  for (int i = 0; i < v.crates; ++i) {
    GreenhouseObstacle o{"crate" + std::to_string(i), "crate"};
    o.x = t.rear_wall_x + 0.3 + 0.3 * detail::unitDraw(rng);
    o.y = t.edge_y_min + 0.5 + span * detail::unitDraw(rng);
    o.yaw = 0.4 * (detail::unitDraw(rng) - 0.5);
    o.half_length = 0.2, o.half_width = 0.3, o.height = 0.3;
    standingBox(t, o, kCrateColour, out);
  }
  std::vector<double> rows = t.plant_row_y;
  for (int i = 0; i < v.trolleys && !rows.empty(); ++i) {
    const size_t k = std::min(rows.size() - 1, static_cast<size_t>(detail::unitDraw(rng) * rows.size()));
    GreenhouseObstacle o{"trolley" + std::to_string(i), "trolley"};
    o.x = v.trolley_x_m, o.y = rows[k], o.yaw = 0.2 * (detail::unitDraw(rng) - 0.5);
    o.half_length = 0.45, o.half_width = 0.25, o.height = 0.9;
    rows.erase(rows.begin() + static_cast<long>(k));
    standingBox(t, o, kTrolleyColour, out);
  }
}

}  // namespace

bool GreenhouseVariation::active() const {
  return pipe_end_offset_m != 0.0 || pipe_gap_probability != 0.0 || rust_probability != 0.0 ||
         headland_slope_deg != 0.0 || headland_bumps != 0 || hoses != 0 || crates != 0 || trolleys != 0 ||
         rail_length_jitter_m != 0.0 || set_spacing_jitter_m != 0.0;
}

void GreenhouseVariation::validate() const {
  requireIn(pipe_end_offset_m, 0.0, 0.1, "pipe_end_offset");
  requireIn(pipe_bend_length_m, 0.05, 5.0, "pipe_bend_length");
  requireIn(pipe_gap_probability, 0.0, 1.0, "pipe_gap_probability");
  requireIn(pipe_gap_m, 0.0, 0.5, "pipe_gap");
  requireIn(rust_probability, 0.0, 1.0, "rust_probability");
  requireIn(headland_slope_deg, 0.0, 10.0, "headland_slope_deg");
  requireIn(headland_bumps, 0, 1000, "headland_bumps");
  requireIn(bump_slope_deg, 0.05, 10.0, "bump_slope_deg");
  requireIn(hoses, 0, 100, "hoses");
  requireIn(crates, 0, 100, "crates");
  requireIn(trolleys, 0, 100, "trolleys");
  requireIn(trolley_x_m, -100.0, -0.3, "trolley_x");
  requireIn(rail_length_jitter_m, 0.0, 100.0, "rail_length_jitter");
  requireIn(set_spacing_jitter_m, 0.0, 1.0, "set_spacing_jitter");
}

GreenhouseVariation greenhouseVariationProfile(const std::string& name) {
  GreenhouseVariation v;
  if (name == "none") return v;
  if (name != "harsh" && name != "pipes")
    throw std::invalid_argument("world_variation: expected none, pipes or harsh, got '" + name + "'");
  v.pipe_end_offset_m = 0.02;
  v.pipe_gap_probability = 0.1;
  v.pipe_gap_m = 0.01;
  v.rust_probability = 0.2;
  if (name == "pipes") return v;  // the pipes alone: a headland as drawn
  v.headland_slope_deg = 1.0;     // with 1 deg bumps: at most 2 deg anywhere on the headland
  v.headland_bumps = 6;
  v.bump_slope_deg = 1.0;
  v.hoses = 2;
  v.crates = 4;
  v.trolleys = 2;
  v.rail_length_jitter_m = 2.0;
  v.set_spacing_jitter_m = 0.05;
  return v;
}

namespace detail {

namespace {
/// Drawn lengths are whole tenths of a millimetre: the truth file's six digits then hold them exactly.
double tenthMm(double v) { return std::round(v * 1e4) / 1e4; }
}  // namespace

RailSetDraws drawRailSets(const GreenhouseParams& p) {
  RailSetDraws d;
  d.rng.seed(p.variation.seed);
  for (int k = 0; k < p.rail_sets; ++k) {
    if (!p.variation.active()) {
      d.set_dy.push_back(0.0), d.shortening.push_back(0.0);
      continue;
    }
    d.set_dy.push_back(tenthMm(p.variation.set_spacing_jitter_m * (2.0 * unitDraw(d.rng) - 1.0)));
    d.shortening.push_back(tenthMm(p.variation.rail_length_jitter_m * unitDraw(d.rng)));
  }
  return d;
}

void writeVariedPipe(const GreenhouseParams& p, double zc, const std::string& name, int side, RailSetTruth& s,
                     RailSetDraws& d, GeomWriter& w) {
  const GreenhouseVariation& v = p.variation;
  const double r = 0.5 * p.pipe_diameter_m, y = s.pipe_y[side];
  const double dy = tenthMm(v.pipe_end_offset_m * (2.0 * unitDraw(d.rng) - 1.0));
  const bool bent = v.pipe_end_offset_m > 0.0;
  s.pipe_start_offset_m[side] = dy;
  s.bend_length_m = bent ? v.pipe_bend_length_m : 0.0;
  // Joints along the pipe's centre line: the start (offset), the end of the bend, then every kPiece.
  std::vector<Eigen::Vector3d> joints{{s.start_x + r, y + dy, zc}};
  const double straight_from = bent ? s.start_x + v.pipe_bend_length_m : s.start_x + r;
  const double end = s.start_x + s.length_m - r;
  const int n = std::max(1, static_cast<int>(std::ceil((end - straight_from) / kPiece)));
  if (bent) joints.emplace_back(straight_from, y, zc);
  for (int k = 1; k <= n; ++k) joints.emplace_back(straight_from + (end - straight_from) * k / n, y, zc);
  std::vector<bool> open(joints.size(), false);
  for (size_t j = 1; j + 1 < joints.size(); ++j) open[j] = unitDraw(d.rng) < v.pipe_gap_probability;
  // A piece at an open joint ends square-cut, as a sawn pipe does, pipe_gap short of the next piece: a capsule
  // to one radius before the cut, then a cylinder to the cut (a capsule's round end alone would open a notch
  // 2 r + pipe_gap wide along the top line, 61 mm for a 1 cm gap, into which a range finder looks down).
  for (size_t k = 0; k + 1 < joints.size(); ++k) {
    Eigen::Vector3d a = joints[k], b = joints[k + 1];
    const Eigen::Vector3d u = (b - a).normalized();
    const Eigen::Vector3d cut_a = a + 0.5 * v.pipe_gap_m * u, cut_b = b - 0.5 * v.pipe_gap_m * u;
    if (open[k]) a = cut_a + r * u;
    if (open[k + 1]) b = cut_b - r * u;
    const bool rusty = unitDraw(d.rng) < v.rust_probability;
    const std::string piece = (rusty ? "rusty_" : "") + name + "_s" + std::to_string(k);
    const char* colour = rusty ? kRustyPipeColour : colours::kPipe;
    w.capsule(piece, a, b, r, colour);
    if (open[k]) w.cylinderBetween(piece + "_cut0", cut_a, a, r, colour);
    if (open[k + 1]) w.cylinderBetween(piece + "_cut1", b, cut_b, r, colour);
  }
}

std::string headlandGeoms(const GreenhouseParams& p, GreenhouseTruth& t, std::mt19937& rng) {
  std::ostringstream out;
  out.precision(9);
  if (t.headland_slope_rad != 0.0) slopedFloor(p, t, out);
  bumps(p, t, rng, out);
  hoses(p, t, rng, out);
  cratesAndTrolleys(p, t, rng, out);
  return out.str();
}

}  // namespace detail
}  // namespace thorvald_sim
