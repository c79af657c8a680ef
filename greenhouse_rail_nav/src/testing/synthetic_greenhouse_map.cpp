#include "greenhouse_rail_nav/testing/synthetic_greenhouse_map.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace greenhouse_rail_nav {
namespace {

/// Paints cells whose centre lies in a layout-frame rectangle [x0, x1] x [y0, y1].
class LayoutPainter {
 public:
  LayoutPainter(thorvald_map::OccupancyGrid* map, const thorvald_base::Pose2D& layout_in_map)
      : map_(map), to_map_(layout_in_map), to_layout_(layout_in_map.inverse()) {}

  void rect(double x0, double x1, double y0, double y1, std::int8_t value) {
    double min_c = 1e18, max_c = -1e18, min_r = 1e18, max_r = -1e18;
    const thorvald_base::Pose2D grid_to_layout = map_->origin.inverse();
    for (const auto& corner :
         {Eigen::Vector2d(x0, y0), Eigen::Vector2d(x1, y0), Eigen::Vector2d(x0, y1), Eigen::Vector2d(x1, y1)}) {
      const Eigen::Vector2d g = grid_to_layout.transformPoint(to_map_.transformPoint(corner)) / map_->resolution_m;
      min_c = std::min(min_c, g.x());
      max_c = std::max(max_c, g.x());
      min_r = std::min(min_r, g.y());
      max_r = std::max(max_r, g.y());
    }
    const int c0 = std::max(0, static_cast<int>(std::floor(min_c)) - 1);
    const int c1 = std::min(map_->width - 1, static_cast<int>(std::ceil(max_c)) + 1);
    const int r0 = std::max(0, static_cast<int>(std::floor(min_r)) - 1);
    const int r1 = std::min(map_->height - 1, static_cast<int>(std::ceil(max_r)) + 1);
    for (int r = r0; r <= r1; ++r) {
      for (int c = c0; c <= c1; ++c) {
        const Eigen::Vector2d p = to_layout_.transformPoint(map_->cellCentre(c, r));
        if (p.x() >= x0 && p.x() <= x1 && p.y() >= y0 && p.y() <= y1) map_->at(c, r) = value;
      }
    }
  }

 private:
  thorvald_map::OccupancyGrid* map_;
  thorvald_base::Pose2D to_map_, to_layout_;
};

}  // namespace

SyntheticGreenhouseMap makeGreenhouseMap(const GreenhouseLayout& layout) {
  std::mt19937 rng(layout.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double width = layout.rail_sets * layout.spacing_m;
  const double t = layout.wall_thickness_m;
  const double rows_depth = layout.headland_depth_m + layout.visible_row_depth_m;
  const double depth = rows_depth + (layout.end_wall_gap_m > 0.0 ? layout.end_wall_gap_m : 0.0);

  // Grid: axis-aligned bounding box of the rotated greenhouse plus margin.
  Eigen::Vector2d lo(1e18, 1e18), hi(-1e18, -1e18);
  const double left_x = -std::max(t, layout.side_walls && layout.left_wall ? 0.0 : layout.floor_beyond_missing_wall_m);
  const double right_x =
      width + std::max(t, layout.side_walls && layout.right_wall ? 0.0 : layout.floor_beyond_missing_wall_m);
  const double far = depth + (layout.end_wall_gap_m > 0.0 ? t : 0.0), extra = layout.end_wall_gap_m > 0.0 ? 0.3 : 0.0;
  for (const auto& corner : {Eigen::Vector2d(left_x - extra, -t), Eigen::Vector2d(right_x + extra, -t),
                             Eigen::Vector2d(left_x - extra, far), Eigen::Vector2d(right_x + extra, far)}) {
    const Eigen::Vector2d p = layout.layout_in_map.transformPoint(corner);
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  lo.array() -= layout.map_margin_m;
  hi.array() += layout.map_margin_m;
  const double res = layout.resolution_m;
  SyntheticGreenhouseMap out;
  out.map = thorvald_map::OccupancyGrid(static_cast<int>(std::ceil((hi.x() - lo.x()) / res)),
                                        static_cast<int>(std::ceil((hi.y() - lo.y()) / res)), res,
                                        thorvald_base::Pose2D(lo.x(), lo.y(), 0.0));
  LayoutPainter paint(&out.map, layout.layout_in_map);
  const std::int8_t occ = thorvald_map::kOccupied, free = thorvald_map::kFree;

  const bool left_wall = layout.side_walls && layout.left_wall;
  const bool right_wall = layout.side_walls && layout.right_wall;
  const double beyond = layout.floor_beyond_missing_wall_m;
  // Free floor seen by the laser: the headland and the first metres of the paths between rows; where a
  // side wall is missing from the map, the laser saw floor beyond it.
  paint.rect(left_wall ? 0.0 : -beyond, right_wall ? width : width + beyond, 0.0, depth, free);
  // Walls.
  const double rear_left = left_wall || layout.rear_wall_ends_at_corner ? -t : -std::max(t, beyond);
  const double rear_right = right_wall || layout.rear_wall_ends_at_corner ? width + t : width + std::max(t, beyond);
  paint.rect(rear_left, rear_right, -t, 0.0, occ);
  if (left_wall) paint.rect(-t, 0.0, -t, depth, occ);
  if (right_wall) paint.rect(width, width + t, -t, depth, occ);
  if (layout.end_wall_gap_m > 0.0) paint.rect(-t - 0.3, width + t + 0.3, depth, depth + t, occ);
  if (layout.door_width_m > 0.0) {
    // A door on the headland in each side wall; the laser saw nothing through it.
    const double y0 = 0.3 + unit(rng) * std::max(0.0, layout.headland_depth_m - layout.door_width_m - 0.6);
    if (left_wall) paint.rect(-t - res, 0.0, y0, y0 + layout.door_width_m, thorvald_map::kUnknown);
    if (right_wall) paint.rect(width, width + t + res, y0, y0 + layout.door_width_m, thorvald_map::kUnknown);
  }
  // Rows: ventilation lines are thin and solid, rows of plants are dotted (pots and stems) and wider.
  for (int j = 1; j < layout.rail_sets; ++j) {
    const bool drawn = layout.visible_rows.empty() ? unit(rng) < layout.row_probability
                                                   : std::find(layout.visible_rows.begin(), layout.visible_rows.end(),
                                                               j) != layout.visible_rows.end();
    if (!drawn) continue;
    out.rows_drawn.push_back(j);
    const double x = j * layout.spacing_m;
    const double y0 = layout.headland_depth_m + layout.row_start_jitter_m * (2.0 * unit(rng) - 1.0);
    const double y_end = rows_depth;
    const bool has_gap = unit(rng) < layout.gap_probability;
    const double gap0 = y0 + 1.0 + unit(rng) * std::max(0.0, y_end - y0 - 2.5), gap1 = gap0 + 0.5 + 0.5 * unit(rng);
    if (unit(rng) < layout.ventilation_fraction) {
      const double half = 0.5 * res;
      if (layout.ventilation_width_m > 0.0) {
        // A tube: its faces and front are what the laser hits; its inside is never seen.
        const double w = 0.5 * layout.ventilation_width_m;
        const bool left_only = std::find(layout.rows_seen_from_left_only.begin(), layout.rows_seen_from_left_only.end(),
                                         j) != layout.rows_seen_from_left_only.end();
        paint.rect(x - w, x + w, y0, y_end, thorvald_map::kUnknown);
        paint.rect(x - w - half, x - w + half, y0, y_end, occ);
        paint.rect(x + w - half, x + w + half, y0, y0 + w, occ);
        if (left_only) {
          paint.rect(x + w - half, x + w + 0.15, y0 + w, y_end, thorvald_map::kUnknown);
        } else {
          paint.rect(x + w - half, x + w + half, y0, y_end, occ);
        }
        paint.rect(x - w, x + w, y0, y0 + res, occ);
      } else if (has_gap) {
        paint.rect(x - half, x + half, y0, gap0, occ);
        paint.rect(x - half, x + half, gap1, y_end, occ);
      } else {
        paint.rect(x - half, x + half, y0, y_end, occ);
      }
    } else {
      for (double y = y0; y < y_end; y += 0.25) {
        if (has_gap && y > gap0 && y < gap1) continue;
        const double half = 0.06 + 0.06 * unit(rng);
        const double dx = 0.04 * (2.0 * unit(rng) - 1.0);
        paint.rect(x + dx - half, x + dx + half, y, std::min(y_end, y + 0.15), occ);
      }
    }
  }
  // Clutter on the headland: boxes and trolleys, kept off the row starts.
  for (int k = 0; k < layout.clutter_objects; ++k) {
    const double sx = 0.3 + 0.7 * unit(rng), sy = 0.3 + 0.4 * unit(rng);
    const double cx = sx + unit(rng) * std::max(0.0, width - 2.0 * sx);
    const double cy = 0.3 + unit(rng) * std::max(0.0, layout.headland_depth_m - 1.2 - sy);
    paint.rect(cx - sx / 2, cx + sx / 2, cy, cy + sy, occ);
  }
  if (layout.clutter_in_line && !out.rows_drawn.empty()) {
    // A box right in front of a row, as wide as a trolley, 0.1-0.4 m before the row starts.
    const int j = out.rows_drawn[static_cast<std::size_t>(unit(rng) * out.rows_drawn.size()) % out.rows_drawn.size()];
    const double sx = 0.4 + 0.4 * unit(rng), sy = 0.4 + 0.6 * unit(rng);
    const double y1 = layout.headland_depth_m - 0.1 - 0.3 * unit(rng);
    paint.rect(j * layout.spacing_m - sx / 2, j * layout.spacing_m + sx / 2, std::max(0.2, y1 - sy), y1, occ);
  }
  for (int k = 0; k < layout.noise_lines; ++k) {
    // A thin line of false cells (a hose, a reflection), 1-2 m long, anywhere on the headland.
    const double length = 1.0 + unit(rng), angle = M_PI * unit(rng);
    const double cx = 1.0 + unit(rng) * std::max(0.0, width - 2.0);
    const double cy = 0.8 + unit(rng) * std::max(0.0, layout.headland_depth_m - 1.6);
    for (double s = -0.5 * length; s <= 0.5 * length; s += 0.5 * res) {
      const double x = cx + s * std::cos(angle), y = cy + s * std::sin(angle);
      paint.rect(x - 0.5 * res, x + 0.5 * res, y - 0.5 * res, y + 0.5 * res, occ);
    }
  }
  // Speckle noise: single false occupied cells anywhere the laser saw free floor.
  if (layout.speckle_free_fraction > 0.0) {
    for (auto& cell : out.map.data) {
      if (cell == free && unit(rng) < layout.speckle_free_fraction) cell = occ;
    }
  }
  // Speckle noise on the headland floor.
  const int speckles = static_cast<int>(layout.speckle_per_m2 * width * layout.headland_depth_m);
  for (int k = 0; k < speckles; ++k) {
    const double x = unit(rng) * width, y = unit(rng) * layout.headland_depth_m;
    paint.rect(x - 0.5 * res, x + 0.5 * res, y - 0.5 * res, y + 0.5 * res, occ);
  }
  for (int i = 0; i < layout.rail_sets; ++i) {
    const Eigen::Vector2d o =
        layout.layout_in_map.transformPoint({(i + 0.5) * layout.spacing_m, layout.headland_depth_m});
    out.rail_frames.emplace_back(o.x(), o.y(), thorvald_base::normalizeAngle(layout.layout_in_map.yaw + M_PI / 2));
  }
  out.edge_start = layout.layout_in_map.transformPoint({0.0, layout.headland_depth_m});
  out.edge_end = layout.layout_in_map.transformPoint({width, layout.headland_depth_m});
  return out;
}

}  // namespace greenhouse_rail_nav
