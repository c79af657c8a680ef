#include "thorvald_navigation/occupancy_mapper.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace thorvald_navigation {
namespace {

constexpr int kWallValue = 65;  // cells at or above are walls for matching (map_server's occupied_thresh 0.65)

std::int8_t occupancyValue(float log_odds) {
  if (log_odds == 0.0f) return thorvald_map::kUnknown;
  const double p = 1.0 - 1.0 / (1.0 + std::exp(static_cast<double>(log_odds)));
  return static_cast<std::int8_t>(std::lround(100.0 * p));
}

}  // namespace

std::string MapperParams::validate() const {
  if (!(resolution_m >= 0.01 && resolution_m <= 1.0)) return "resolution must be in [0.01, 1] m";
  if (!(initial_size_m >= 1.0)) return "initial_size must be >= 1 m";
  if (!(max_size_m >= initial_size_m) || max_size_m / resolution_m > 20000.0)
    return "max_size must be >= initial_size and at most 20000 cells";
  if (!(max_range_m > 0.0)) return "max_range must be > 0";
  if (!(hit_log_odds > 0.0) || !(miss_log_odds < 0.0) || !(clamp_log_odds > 0.0))
    return "hit_log_odds must be > 0, miss_log_odds < 0, clamp_log_odds > 0";
  if (!(linear_update_m >= 0.0) || !(angular_update_rad >= 0.0)) return "linear/angular update must be >= 0";
  if (!(field_max_distance_m > 0.0)) return "field_max_distance must be > 0";
  if (!(min_inlier_fraction >= 0.0 && min_inlier_fraction <= 1.0)) return "min_inlier_fraction must be in [0, 1]";
  if (!(odom_sigma_xy_m >= 0.0) || !(odom_sigma_yaw_rad >= 0.0) || !(odom_sigma_fraction >= 0.0))
    return "odom_sigma_xy, odom_sigma_yaw and odom_sigma_fraction must be >= 0";
  if (!(surfel_half_length_m >= 0.0)) return "surfel_half_length must be >= 0 (0: the whole line)";
  if (!(grazing_keep_max_m >= 0.0) || !(grazing_neighbour_gap_m > 0.0))
    return "grazing_keep_max must be >= 0 and grazing_neighbour_gap > 0";
  return matcher.validate();
}

OccupancyMapper::OccupancyMapper(const MapperParams& params) : params_(params) {}

void OccupancyMapper::ensureInside(const Eigen::Vector2d& p) {
  const Eigen::Vector2i c = geometry_.cellOf(p);
  if (geometry_.inside(c.x(), c.y())) return;
  // Grow by at least half the current size on the side that is short, so growth is amortised.
  const double res = params_.resolution_m;
  const double grow = std::max(5.0, 0.5 * std::max(geometry_.width, geometry_.height) * res);
  double x0 = geometry_.origin.x, y0 = geometry_.origin.y;
  double x1 = x0 + geometry_.width * res, y1 = y0 + geometry_.height * res;
  if (p.x() < x0) x0 = p.x() - grow;
  if (p.y() < y0) y0 = p.y() - grow;
  if (p.x() >= x1) x1 = p.x() + grow;
  if (p.y() >= y1) y1 = p.y() + grow;
  if (x1 - x0 > params_.max_size_m || y1 - y0 > params_.max_size_m) return;  // caller drops the point
  const int dx = std::max(0, static_cast<int>(std::ceil((geometry_.origin.x - x0) / res)));
  const int dy = std::max(0, static_cast<int>(std::ceil((geometry_.origin.y - y0) / res)));
  const double new_ox = geometry_.origin.x - dx * res, new_oy = geometry_.origin.y - dy * res;
  const int w = std::max(dx + geometry_.width, static_cast<int>(std::ceil((x1 - new_ox) / res)));
  const int h = std::max(dy + geometry_.height, static_cast<int>(std::ceil((y1 - new_oy) / res)));
  std::vector<float> grown(static_cast<std::size_t>(w) * h, 0.0f), grown_hits(grown.size(), 0.0f);
  std::vector<Eigen::Vector2f> grown_mean(grown.size(), Eigen::Vector2f::Zero());
  for (int y = 0; y < geometry_.height; ++y) {
    const std::ptrdiff_t from = static_cast<std::ptrdiff_t>(y) * geometry_.width;
    const std::ptrdiff_t to = static_cast<std::ptrdiff_t>(y + dy) * w + dx;
    std::copy_n(log_odds_.begin() + from, geometry_.width, grown.begin() + to);
    std::copy_n(surface_.hits.begin() + from, geometry_.width, grown_hits.begin() + to);
    std::copy_n(surface_.mean_m.begin() + from, geometry_.width, grown_mean.begin() + to);
  }
  log_odds_.swap(grown);
  thorvald_map::OccupancyGrid occupancy(w, h, res, geometry_.origin.x - dx * res, geometry_.origin.y - dy * res,
                                        thorvald_map::kUnknown);
  for (int y = 0; y < geometry_.height; ++y)
    std::copy_n(occupancy_.data.begin() + static_cast<std::ptrdiff_t>(y) * geometry_.width, geometry_.width,
                occupancy.data.begin() + static_cast<std::ptrdiff_t>(y + dy) * w + dx);
  occupancy_ = std::move(occupancy);
  surface_.hits.swap(grown_hits);
  surface_.mean_m.swap(grown_mean);
  geometry_.width = w;
  geometry_.height = h;
  geometry_.origin.x -= dx * res;
  geometry_.origin.y -= dy * res;
}

bool OccupancyMapper::update(const Eigen::Vector2i& c, double log_odds) {
  if (!geometry_.inside(c.x(), c.y())) return false;
  const std::size_t i = geometry_.index(c.x(), c.y());
  if (scan_stamp_[i] == scan_counter_) return false;  // already updated by this scan
  scan_stamp_[i] = scan_counter_;
  const float clamp = static_cast<float>(params_.clamp_log_odds);
  log_odds_[i] = std::clamp(log_odds_[i] + static_cast<float>(log_odds), -clamp, clamp);
  touched_.push_back(static_cast<int>(i));
  return true;
}

// Walks the cells that the segment itself crosses (Amanatides and Woo), not a line between cell centres: near its end
// a beam that meets a wall at a grazing angle crosses only the part of the wall's cells in front of the face, where a
// centre-to-centre line would already run through the face's row of cells and clear it.
void OccupancyMapper::traceFree(const Eigen::Vector2d& from, const Eigen::Vector2d& to, bool no_return,
                                const GrazedFace& face) {
  const Eigen::Vector2i a = geometry_.cellOf(from), b = geometry_.cellOf(to);
  if (!geometry_.inside(a.x(), a.y()) || !geometry_.inside(b.x(), b.y())) return;
  const double res = geometry_.resolution_m;
  const Eigen::Vector2d d = to - from;
  const int sx = d.x() > 0.0 ? 1 : -1, sy = d.y() > 0.0 ? 1 : -1;
  // Ray parameter t in [0, 1] at the next vertical / horizontal cell border, and its step per cell.
  const double inf = std::numeric_limits<double>::infinity();
  const double next_x = geometry_.origin.x + (a.x() + (sx > 0 ? 1 : 0)) * res;
  const double next_y = geometry_.origin.y + (a.y() + (sy > 0 ? 1 : 0)) * res;
  double t_x = std::abs(d.x()) > 1e-12 ? (next_x - from.x()) / d.x() : inf;
  double t_y = std::abs(d.y()) > 1e-12 ? (next_y - from.y()) / d.y() : inf;
  const double dt_x = std::abs(d.x()) > 1e-12 ? res / std::abs(d.x()) : inf;
  const double dt_y = std::abs(d.y()) > 1e-12 ? res / std::abs(d.y()) : inf;
  int x = a.x(), y = a.y();
  double t_enter = 0.0;  // where the segment entered the current cell
  const int max_steps = std::abs(b.x() - a.x()) + std::abs(b.y() - a.y());
  for (int step = 0; step < max_steps && (x != b.x() || y != b.y()); ++step) {
    const bool keep = t_enter >= face.from_t && face.crosses(geometry_.cellCentre(x, y), res);
    if (!keep && !(no_return && holdsEnds({x, y}))) update({x, y}, params_.miss_log_odds);
    t_enter = std::min(t_x, t_y);
    if (t_x < t_y) {
      x += sx;
      t_x += dt_x;
    } else {
      y += sy;
      t_y += dt_y;
    }
  }
  if (no_return && !holdsEnds(b)) update(b, params_.miss_log_odds);
}

bool OccupancyMapper::holdsEnds(const Eigen::Vector2i& c) const {
  return params_.no_return_keeps_ends && geometry_.inside(c.x(), c.y()) &&
         surface_.hits[geometry_.index(c.x(), c.y())] > 0.0f;
}

MapperUpdate OccupancyMapper::addScan(const thorvald_base::Pose2D& odom, const Eigen::Vector2d& sensor_base,
                                      const std::vector<Eigen::Vector2d>& points_base,
                                      const std::vector<Eigen::Vector2d>& free_ends_base) {
  MapperUpdate u;
  if (!odom.finite()) {
    u.rejected = "odometry pose is not finite";
    return u;
  }
  if (points_base.size() < 10) {
    u.rejected = "scan has fewer than 10 valid beams";
    return u;
  }
  if (first_) {
    const double half = 0.5 * params_.initial_size_m;
    const int n = static_cast<int>(std::ceil(params_.initial_size_m / params_.resolution_m));
    geometry_ =
        thorvald_map::OccupancyGrid(n, n, params_.resolution_m, odom.x - half, odom.y - half, thorvald_map::kUnknown);
    geometry_.data.clear();
    log_odds_.assign(static_cast<std::size_t>(n) * n, 0.0f);
    occupancy_ = thorvald_map::OccupancyGrid(n, n, params_.resolution_m, geometry_.origin.x, geometry_.origin.y,
                                             thorvald_map::kUnknown);
    surface_.hits.assign(log_odds_.size(), 0.0f);
    surface_.mean_m.assign(log_odds_.size(), Eigen::Vector2f::Zero());
    map_to_odom_ = thorvald_base::Pose2D{};
  } else {
    const thorvald_base::Pose2D delta = last_integrated_odom_.inverse() * odom;
    if (std::hypot(delta.x, delta.y) < params_.linear_update_m && std::abs(delta.yaw) < params_.angular_update_rad) {
      u.pose = map_to_odom_ * odom;
      return u;
    }
  }
  thorvald_base::Pose2D pose = map_to_odom_ * odom;
  if (!first_) {
    // Rebuilt for every scan (README, Limits).
    if (params_.match_surface) {
      const thorvald_map::WallSurface surface = wallSurface();
      field_ = DistanceField(occupancyGrid(), params_.field_max_distance_m, kWallValue, true, &surface,
                             params_.surfel_half_length_m);
    } else {
      field_ = DistanceField(occupancyGrid(), params_.field_max_distance_m, kWallValue, true);
    }
    ScanMatcherParams matcher = params_.matcher;
    const thorvald_base::Pose2D moved = last_integrated_odom_.inverse() * odom;
    if (params_.odom_sigma_xy_m > 0.0)
      matcher.prior_sigma_xy_m = params_.odom_sigma_xy_m + params_.odom_sigma_fraction * std::hypot(moved.x, moved.y);
    if (params_.odom_sigma_yaw_rad > 0.0)
      matcher.prior_sigma_yaw_rad = params_.odom_sigma_yaw_rad + params_.odom_sigma_fraction * std::abs(moved.yaw);
    const MatchResult m = matchScan(field_, points_base, pose, matcher);
    u.inlier_fraction = m.inlier_fraction;
    if (m.inlier_fraction >= params_.min_inlier_fraction && m.pose.finite()) {
      pose = m.pose;
      u.matched = true;
      map_to_odom_ = pose * odom.inverse();
    }
  }
  insert(pose, sensor_base, points_base, free_ends_base);
  first_ = false;
  last_integrated_odom_ = odom;
  ++scans_used_;
  u.integrated = true;
  u.pose = pose;
  return u;
}

OccupancyMapper::GrazedFace OccupancyMapper::grazedFace(const Eigen::Vector2d& origin,
                                                        const std::vector<Eigen::Vector2d>& hits, std::size_t i) const {
  GrazedFace face;
  if (params_.grazing_keep_max_m <= 0.0 || i == 0 || i + 1 >= hits.size()) return face;
  const Eigen::Vector2d t = hits[i + 1] - hits[i - 1];
  const double len = t.norm();
  if (len < 1e-9 || len > params_.grazing_neighbour_gap_m) return face;
  const Eigen::Vector2d n(-t.y() / len, t.x() / len);
  const double res = params_.resolution_m;
  if (std::abs(n.dot(hits[i] - hits[i - 1])) > res) return face;  // a corner or two surfaces, not one face
  const Eigen::Vector2d ray = hits[i] - origin;
  const double r = ray.norm();
  const double sin_angle = r > 1e-9 ? std::abs(n.dot(ray)) / r : 1.0;
  if (sin_angle >= 1.0) return face;
  const double keep = std::min(params_.grazing_keep_max_m, res * (1.0 / std::max(sin_angle, 1e-6) - 1.0));
  face.from_t = std::max(0.0, 1.0 - keep / r);
  face.point = hits[i];
  face.normal = n;
  return face;
}

// Every cell is updated at most once per scan, and a beam's end before any beam's free space: a beam that grazes a
// wall crosses the cells holding the wall's face (their free part) before it ends, and without this those cells would
// be cleared by the many grazing beams of each scan and the wall drawn behind its face, the headland too wide.
void OccupancyMapper::insert(const thorvald_base::Pose2D& pose, const Eigen::Vector2d& sensor_base,
                             const std::vector<Eigen::Vector2d>& points_base,
                             const std::vector<Eigen::Vector2d>& free_ends_base) {
  const Eigen::Vector2d origin = pose.transformPoint(sensor_base);
  std::vector<Eigen::Vector2d> hits, free_ends;
  hits.reserve(points_base.size());
  free_ends.reserve(points_base.size() + free_ends_base.size());
  auto clipped = [&](const Eigen::Vector2d& p) {
    const Eigen::Vector2d rel = p - sensor_base;
    const double r = rel.norm();
    return pose.transformPoint(r > params_.max_range_m ? Eigen::Vector2d(sensor_base + rel * (params_.max_range_m / r))
                                                       : p);
  };
  for (const auto& p : points_base) {
    if ((p - sensor_base).norm() > params_.max_range_m)
      free_ends.push_back(clipped(p));
    else
      hits.push_back(pose.transformPoint(p));
  }
  for (const auto& p : free_ends_base) free_ends.push_back(clipped(p));
  ensureInside(origin);
  for (const auto& p : hits) ensureInside(p);
  for (const auto& p : free_ends) ensureInside(p);
  if (scan_stamp_.size() != log_odds_.size()) scan_stamp_.assign(log_odds_.size(), 0);
  if (++scan_counter_ == 0) {  // wrapped: forget every stamp
    std::fill(scan_stamp_.begin(), scan_stamp_.end(), 0);
    scan_counter_ = 1;
  }
  for (const auto& p : hits) {
    const Eigen::Vector2i c = geometry_.cellOf(p);
    update(c, params_.hit_log_odds);
    if (!geometry_.inside(c.x(), c.y())) continue;
    // Every end point counts towards its cell's mean (the once-per-scan rule is for the occupancy only).
    const std::size_t i = geometry_.index(c.x(), c.y());
    const float h = ++surface_.hits[i];
    surface_.mean_m[i] += (p.cast<float>() - surface_.mean_m[i]) / h;
  }
  for (std::size_t i = 0; i < hits.size(); ++i) {
    traceFree(origin, hits[i], false, grazedFace(origin, hits, i));  // not the end cell: the hit is there
  }
  for (const auto& p : free_ends) traceFree(origin, p, true, GrazedFace{});
  // The occupancy values of the cells this scan updated.
  for (const int i : touched_)
    occupancy_.data[static_cast<std::size_t>(i)] = occupancyValue(log_odds_[static_cast<std::size_t>(i)]);
  touched_.clear();
}

Eigen::Vector4i OccupancyMapper::observedBounds() const {
  int x0 = geometry_.width, y0 = geometry_.height, x1 = -1, y1 = -1;
  for (int y = 0; y < geometry_.height; ++y)
    for (int x = 0; x < geometry_.width; ++x)
      if (log_odds_[geometry_.index(x, y)] != 0.0f) {
        x0 = std::min(x0, x);
        y0 = std::min(y0, y);
        x1 = std::max(x1, x);
        y1 = std::max(y1, y);
      }
  if (x1 < 0) return {0, 0, -1, -1};
  return {std::max(0, x0 - 2), std::max(0, y0 - 2), std::min(geometry_.width - 1, x1 + 2),
          std::min(geometry_.height - 1, y1 + 2)};
}

thorvald_map::OccupancyGrid OccupancyMapper::occupancyGrid() const {
  if (log_odds_.empty())
    return thorvald_map::OccupancyGrid(1, 1, params_.resolution_m, 0.0, 0.0, thorvald_map::kUnknown);
  const Eigen::Vector4i b = observedBounds();
  const int x0 = b[0], y0 = b[1], x1 = b[2], y1 = b[3];
  if (x1 < 0)
    return thorvald_map::OccupancyGrid(1, 1, params_.resolution_m, geometry_.origin.x, geometry_.origin.y,
                                       thorvald_map::kUnknown);
  thorvald_map::OccupancyGrid g(x1 - x0 + 1, y1 - y0 + 1, params_.resolution_m,
                                geometry_.origin.x + x0 * params_.resolution_m,
                                geometry_.origin.y + y0 * params_.resolution_m, thorvald_map::kUnknown);
  for (int y = y0; y <= y1; ++y)
    std::copy_n(occupancy_.data.begin() + static_cast<std::ptrdiff_t>(geometry_.index(x0, y)), x1 - x0 + 1,
                g.data.begin() + static_cast<std::ptrdiff_t>(g.index(0, y - y0)));
  return g;
}

thorvald_map::WallSurface OccupancyMapper::wallSurface() const {
  thorvald_map::WallSurface s;
  if (log_odds_.empty()) {
    s.hits.assign(1, 0.0f);
    s.mean_m.assign(1, Eigen::Vector2f::Zero());
    return s;
  }
  const Eigen::Vector4i b = observedBounds();
  if (b[2] < 0) {
    s.hits.assign(1, 0.0f);
    s.mean_m.assign(1, Eigen::Vector2f::Zero());
    return s;
  }
  const int w = b[2] - b[0] + 1, h = b[3] - b[1] + 1;
  s.hits.reserve(static_cast<std::size_t>(w) * h);
  s.mean_m.reserve(static_cast<std::size_t>(w) * h);
  for (int y = b[1]; y <= b[3]; ++y)
    for (int x = b[0]; x <= b[2]; ++x) {
      const std::size_t i = geometry_.index(x, y);
      s.hits.push_back(surface_.hits[i]);
      s.mean_m.push_back(surface_.mean_m[i]);
    }
  return s;
}

double OccupancyMapper::knownAreaM2() const {
  std::size_t n = 0;
  for (float l : log_odds_) n += l != 0.0f;
  return static_cast<double>(n) * params_.resolution_m * params_.resolution_m;
}

}  // namespace thorvald_navigation
