#include "thorvald_sim/greenhouse_world.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <random>
#include <sstream>
#include <stdexcept>

#include "thorvald_sim/geom_writer.h"
#include "greenhouse_variation_geoms.h"
#include "world_checks.h"

namespace thorvald_sim {

using detail::requirePositive;

namespace {

/// Long static geoms are written in pieces of at most this length [m] (see GeomWriter::capsulePieces).
constexpr double kPiece = 2.0;

void validateGreenhouseParams(const GreenhouseParams& p) {
  if (p.rail_sets < 1) throw std::invalid_argument("rail_sets must be at least 1");
  requirePositive(p.set_spacing_m, "set_spacing");
  requirePositive(p.rail_gauge_m, "rail_gauge");
  requirePositive(p.pipe_diameter_m, "pipe_diameter");
  requirePositive(p.rail_length_m, "rail_length");
  requirePositive(p.headland_depth_m, "headland_depth");
  requirePositive(p.row_ground_drop_m, "row_ground_drop");
  requirePositive(p.wall_margin_m, "wall_margin");
  if (p.rail_gauge_m + p.pipe_diameter_m >= p.set_spacing_m)
    throw std::invalid_argument("rail_gauge + pipe_diameter must be below set_spacing");
  if (p.rail_top_m - p.pipe_diameter_m <= -p.row_ground_drop_m)
    throw std::invalid_argument("rail_top must leave the pipes above the rows' ground (row_ground_drop)");
  if (p.vent_every < 0) throw std::invalid_argument("vent_every must be 0 (none) or positive");
  if (!(p.plant_bottom_m >= 0.0 && p.plant_bottom_m < p.plant_top_m))
    throw std::invalid_argument("plant_bottom must be at least 0 and below plant_top (" +
                                std::to_string(p.plant_top_m) + " m)");
  if (!(p.plant_row_start_m >= 0.0 && p.plant_row_end_gap_m >= 0.0))
    throw std::invalid_argument("plant_row_start and plant_row_end_gap must be at least 0");
  p.variation.validate();
  if (p.rail_gauge_m + p.pipe_diameter_m + 2.0 * p.variation.set_spacing_jitter_m >= p.set_spacing_m)
    throw std::invalid_argument(
        "variation/set_spacing_jitter: neighbouring rail sets would touch (rail_gauge + "
        "pipe_diameter + 2 x jitter must be below set_spacing)");
  if (p.variation.rail_length_jitter_m > p.rail_length_m - 1.0)
    throw std::invalid_argument("variation/rail_length_jitter must leave rail sets at least 1 m long");
  if (p.variation.trolley_x_m < -p.headland_depth_m + 0.5)
    throw std::invalid_argument("variation/trolley_x must lie on the headland (above -headland_depth + 0.5 m)");
}

/// The greenhouse's edges, floors and walls (no rail sets or rows yet).
GreenhouseTruth greenhouseFrame(const GreenhouseParams& p) {
  GreenhouseTruth t;
  t.params = p;
  const double r = 0.5 * p.pipe_diameter_m;
  const double y_min = -p.wall_margin_m, y_max = (p.rail_sets - 1) * p.set_spacing_m + p.wall_margin_m;
  t.edge_x = 0.0;
  t.edge_y_min = y_min;
  t.edge_y_max = y_max;
  t.floor_z = 0.0;
  t.row_ground_z = -p.row_ground_drop_m;
  t.pipe_centre_z = p.rail_top_m - r;
  t.rear_wall_x = -p.headland_depth_m;
  t.end_wall_x = p.rail_length_m + p.rail_start_gap_m + 1.0;
  t.side_wall_y[0] = y_min;
  t.side_wall_y[1] = y_max;
  t.headland_slope_rad = p.variation.headland_slope_deg * M_PI / 180.0;
  return t;
}

/// Each rail set: two pipes on their supports.
void writeRailSets(const GreenhouseParams& p, GreenhouseTruth& t, GeomWriter& w, detail::RailSetDraws& draws) {
  const double r = 0.5 * p.pipe_diameter_m;
  for (int k = 0; k < p.rail_sets; ++k) {
    RailSetTruth s;
    s.index = k;
    s.start_x = p.rail_start_gap_m;
    s.start_y = k * p.set_spacing_m + draws.set_dy[k];
    s.length_m = p.rail_length_m - draws.shortening[k];
    s.pipe_y[0] = s.start_y - 0.5 * p.rail_gauge_m;
    s.pipe_y[1] = s.start_y + 0.5 * p.rail_gauge_m;
    for (int side = 0; side < 2; ++side) {
      const std::string name = "rail" + std::to_string(k) + (side == 0 ? "_right" : "_left");
      if (p.variation.active()) {
        detail::writeVariedPipe(p, t.pipe_centre_z, name, side, s, draws, w);
      } else {
        w.capsulePieces(name, {s.start_x + r, s.pipe_y[side], t.pipe_centre_z},
                        {s.start_x + p.rail_length_m - r, s.pipe_y[side], t.pipe_centre_z}, r, colours::kPipe, kPiece);
      }
      const double support_h = t.pipe_centre_z - r - t.row_ground_z;
      int n = 0;
      for (double x = s.start_x + 0.5; x < s.start_x + s.length_m; x += p.support_spacing_m, ++n) {
        w.box(name + "_support" + std::to_string(n), {x, s.pipe_y[side], t.row_ground_z + 0.5 * support_h},
              {0.03, 0.04, 0.5 * support_h}, colours::kSupport);
      }
    }
    t.rail_sets.push_back(s);
  }
}

/// Plant rows hang between neighbouring sets and outside the outer ones (where they fit inside the side walls: a
/// wall_margin of half the set spacing puts the side walls where the outer rows would be); ventilation lines under
/// some.
void writePlantRowsAndVents(const GreenhouseParams& p, GreenhouseTruth& t, GeomWriter& w,
                            const detail::RailSetDraws& draws) {
  const double y_min = t.edge_y_min, y_max = t.edge_y_max;
  const double row_len = p.rail_length_m;
  for (int k = 0; k <= p.rail_sets; ++k) {
    // Midway between the (moved) neighbouring sets; an outer row moves with its set.
    const int left = std::max(0, k - 1), right = std::min(p.rail_sets - 1, k);
    const double dy = 0.5 * (draws.set_dy[left] + draws.set_dy[right]);
    const double y = (k - 0.5) * p.set_spacing_m + dy;
    const bool fits = y - 0.5 * p.plant_width_m > y_min && y + 0.5 * p.plant_width_m < y_max;
    // Along the shorter of the two sets beside it (their starts are one line, rail_start_gap past the edge).
    const double set_len = std::min(t.rail_sets[left].length_m, t.rail_sets[right].length_m);
    const double from = p.plant_row_start_m, to = set_len - p.plant_row_end_gap_m;
    if (fits && to > from) {
      t.plant_row_y.push_back(y);
      const double zc = 0.5 * (p.plant_bottom_m + p.plant_top_m);
      w.boxPieces("plant_row" + std::to_string(k), {p.rail_start_gap_m + 0.5 * (from + to), y, zc},
                  {0.5 * (to - from), 0.5 * p.plant_width_m, 0.5 * (p.plant_top_m - p.plant_bottom_m)}, colours::kPlant,
                  kPiece);
      for (int s : {left, right}) {
        RailSetTruth& set = t.rail_sets[s];
        if (set.plants_to_m <= set.plants_from_m) set.plants_from_m = from, set.plants_to_m = to;
        set.plants_to_m = std::max(set.plants_to_m, to);
      }
    }
    if (p.vent_every > 0 && k > 0 && k < p.rail_sets && k % p.vent_every == 1 % p.vent_every) {
      t.vent_line_y.push_back(y);
      w.capsulePieces("vent_line" + std::to_string(k), {0.5 * p.vent_diameter_m, y, p.vent_height_m},
                      {row_len, y, p.vent_height_m}, 0.5 * p.vent_diameter_m, colours::kVent, kPiece);
    }
  }
}

void writeWalls(const GreenhouseParams& p, const GreenhouseTruth& t, GeomWriter& w) {
  const double y_min = t.edge_y_min, y_max = t.edge_y_max, x_far = t.end_wall_x;
  const double h = p.wall_height_m, zc = t.row_ground_z + 0.5 * (h - t.row_ground_z);
  const double hz = 0.5 * (h - t.row_ground_z), ym = 0.5 * (y_min + y_max), hy = 0.5 * (y_max - y_min) + 0.1;
  w.boxPieces("rear_wall", {t.rear_wall_x - 0.1, ym, zc}, {0.1, hy, hz}, colours::kWall, kPiece);
  w.boxPieces("end_wall", {x_far + 0.1, ym, zc}, {0.1, hy, hz}, colours::kWall, kPiece);
  const double xm = 0.5 * (t.rear_wall_x + x_far), hx = 0.5 * (x_far - t.rear_wall_x) + 0.2;
  w.boxPieces("side_wall_right", {xm, y_min - 0.1, zc}, {hx, 0.1, hz}, colours::kWall, kPiece);
  w.boxPieces("side_wall_left", {xm, y_max + 0.1, zc}, {hx, 0.1, hz}, colours::kWall, kPiece);
}

}  // namespace

WorldDescription makeGreenhouseWorld(const GreenhouseParams& p, GreenhouseTruth* truth) {
  validateGreenhouseParams(p);
  GreenhouseTruth t = greenhouseFrame(p);
  GeomWriter w;
  w.plane("row_ground", {0, 0, t.row_ground_z}, 200.0, colours::kSoil);
  const double y_min = t.edge_y_min, y_max = t.edge_y_max;
  if (t.headland_slope_rad == 0.0)
    w.boxPieces("headland_floor", {-0.5 * p.headland_depth_m, 0.5 * (y_min + y_max), 0.5 * t.row_ground_z},
                {0.5 * p.headland_depth_m, 0.5 * (y_max - y_min), 0.5 * p.row_ground_drop_m}, colours::kConcrete,
                kPiece);
  detail::RailSetDraws draws = detail::drawRailSets(p);
  writeRailSets(p, t, w, draws);
  writePlantRowsAndVents(p, t, w, draws);
  writeWalls(p, t, w);
  std::string extras;
  if (p.variation.active()) extras = detail::headlandGeoms(p, t, draws.rng);
  if (truth) *truth = t;
  return {"greenhouse", w.str() + extras, 0.0};
}

double GreenhouseTruth::floorHeightAt(double x, double /*y*/) const {
  if (x > edge_x) return row_ground_z;
  return floor_z + (edge_x - x) * std::tan(headland_slope_rad);
}

bool writeGreenhouseTruth(const GreenhouseTruth& t, const std::string& path) {
  std::ofstream out(path);
  if (!out) return false;
  out.precision(6);
  out << "# Ground truth written by thorvald_sim's greenhouse generator. Metres, radians, world frame:\n"
      << "# origin on the headland edge, x along the rows, z = 0 the headland floor.\n"
      << "edge: {x: " << t.edge_x << ", y_min: " << t.edge_y_min << ", y_max: " << t.edge_y_max << "}\n"
      << "floor_z: " << t.floor_z << "\nrow_ground_z: " << t.row_ground_z << "\n"
      << "rail_gauge: " << t.params.rail_gauge_m << "\npipe_diameter: " << t.params.pipe_diameter_m
      << "\nrail_top_z: " << t.params.rail_top_m << "\nrail_length: " << t.params.rail_length_m
      << "\nset_spacing: " << t.params.set_spacing_m << "\nrail_sets:\n";
  const bool varied = t.params.variation.active();
  for (const auto& s : t.rail_sets) {
    out << "  - {index: " << s.index << ", x: " << s.start_x << ", y: " << s.start_y << ", yaw: " << s.yaw
        << ", pipe_y: [" << s.pipe_y[0] << ", " << s.pipe_y[1] << "]";
    // A varied greenhouse says where each set's pipes really are: its length and the bent start ends.
    if (varied)
      out << ", length: " << s.length_m << ", pipe_start_offset: [" << s.pipe_start_offset_m[0] << ", "
          << s.pipe_start_offset_m[1] << "], bend_length: " << s.bend_length_m;
    // The plants beside it, along it from its start (none: an empty list).
    if (s.plants_to_m > s.plants_from_m)
      out << ", plants: [" << s.plants_from_m << ", " << s.plants_to_m << "]";
    else
      out << ", plants: []";
    out << "}\n";
  }
  out << "vent_line_y: [";
  for (size_t i = 0; i < t.vent_line_y.size(); ++i) out << (i ? ", " : "") << t.vent_line_y[i];
  out << "]\nplant_row_y: [";
  for (size_t i = 0; i < t.plant_row_y.size(); ++i) out << (i ? ", " : "") << t.plant_row_y[i];
  out << "]\nwalls: {rear_x: " << t.rear_wall_x << ", end_x: " << t.end_wall_x << ", side_y: [" << t.side_wall_y[0]
      << ", " << t.side_wall_y[1] << "]}\n";
  if (varied) {
    out << "variation_seed: " << t.params.variation.seed << "\nheadland_slope: " << t.headland_slope_rad
        << "\nbumps:\n";
    for (const auto& b : t.bumps) out << "  - [" << b.x() << ", " << b.y() << ", " << b.z() << "]\n";
    out << "obstacles:\n";
    for (const auto& o : t.obstacles)
      out << "  - {name: " << o.name << ", kind: " << o.kind << ", x: " << o.x << ", y: " << o.y << ", yaw: " << o.yaw
          << ", half_length: " << o.half_length << ", half_width: " << o.half_width << ", height: " << o.height
          << "}\n";
  }
  return static_cast<bool>(out);
}

}  // namespace thorvald_sim
