#include "thorvald_navigation/costmap.h"

#include <algorithm>
#include <cmath>

namespace thorvald_navigation {

const char* blockerName(Blocker b) {
  switch (b) {
    case Blocker::kNone:
      return "free";
    case Blocker::kWall:
      return "a wall of the map";
    case Blocker::kUnknown:
      return "unmapped space";
    case Blocker::kKeepOut:
      return "the keep-out zone beyond the headland edge";
    case Blocker::kObstacle:
      return "an obstacle seen by the lidar";
  }
  return "?";
}

double Footprint::circumscribedRadius() const {
  double r = 0.0;
  for (const auto& p : polygon) r = std::max(r, p.norm());
  return r;
}

double Footprint::halfWidth() const {
  if (polygon.empty()) return 0.0;
  Eigen::Vector2d lo = polygon[0], hi = polygon[0];
  for (const auto& p : polygon) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return 0.5 * std::min(hi.x() - lo.x(), hi.y() - lo.y());
}

std::string Footprint::check() const {
  if (polygon.size() < 3) return "footprint needs at least 3 points";
  double area2 = 0.0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const auto& a = polygon[i];
    const auto& b = polygon[(i + 1) % polygon.size()];
    if (!a.allFinite()) return "footprint point " + std::to_string(i) + " is not finite";
    area2 += a.x() * b.y() - b.x() * a.y();
  }
  if (std::abs(area2) < 1e-6) return "footprint has no area";
  return {};
}

Footprint rectangleFootprint(double x_min, double x_max, double y_min, double y_max) {
  return Footprint{{{x_min, y_min}, {x_max, y_min}, {x_max, y_max}, {x_min, y_max}}};
}

std::string CostmapParams::validate() const {
  if (!(planning_radius_m >= 0.0) || !std::isfinite(planning_radius_m)) return "planning_radius must be >= 0";
  if (!(inflation_radius_m >= planning_radius_m) || !std::isfinite(inflation_radius_m))
    return "inflation_radius must be >= planning_radius";
  if (!(cost_scaling > 0.0)) return "cost_scaling must be > 0";
  if (!(known_structure_tolerance_m >= 0.0) || !(known_structure_tolerance_m <= 1.0))
    return "known_structure_tolerance must be within [0, 1] m";
  return {};
}

Costmap::Costmap(const thorvald_map::OccupancyGrid& map, const thorvald_map::OccupancyGrid& keep_out,
                 const CostmapParams& params)
    : params_(params),
      geometry_(map.width, map.height, map.resolution_m, map.origin.x, map.origin.y, thorvald_map::kFree) {
  geometry_.data.clear();
  const std::size_t n = static_cast<std::size_t>(map.width) * map.height;
  static_blocker_.assign(n, static_cast<std::uint8_t>(Blocker::kNone));
  const bool use_keep_out = keep_out.width > 0 && keep_out.check().empty();
  for (int y = 0; y < map.height; ++y) {
    for (int x = 0; x < map.width; ++x) {
      const int v = map.at(x, y);
      Blocker b = Blocker::kNone;
      if (v >= 65) {
        b = Blocker::kWall;
      } else if (v < 0 && params_.unknown_is_blocked) {
        b = Blocker::kUnknown;
      }
      if (b == Blocker::kNone && use_keep_out) {
        const Eigen::Vector2i k = keep_out.cellOf(geometry_.cellCentre(x, y));
        if (keep_out.inside(k.x(), k.y()) && keep_out.at(k.x(), k.y()) >= 65) b = Blocker::kKeepOut;
      }
      static_blocker_[geometry_.index(x, y)] = static_cast<std::uint8_t>(b);
    }
  }
  blocker_ = static_blocker_;
  // Distance to the known structure (walls and keep-out; not unknown space, which holds nothing known).
  thorvald_map::OccupancyGrid known(geometry_.width, geometry_.height, geometry_.resolution_m, geometry_.origin.x,
                                    geometry_.origin.y, thorvald_map::kFree);
  for (std::size_t i = 0; i < static_blocker_.size(); ++i)
    if (static_blocker_[i] == static_cast<std::uint8_t>(Blocker::kWall) ||
        static_blocker_[i] == static_cast<std::uint8_t>(Blocker::kKeepOut))
      known.data[i] = thorvald_map::kOccupied;
  const DistanceField field(known, params_.known_structure_tolerance_m + 2.0 * geometry_.resolution_m);
  known_distance_.assign(n, 0.0f);
  for (int y = 0; y < geometry_.height; ++y)
    for (int x = 0; x < geometry_.width; ++x)
      known_distance_[geometry_.index(x, y)] = static_cast<float>(field.cellDistance(x, y));
  blocked_ = thorvald_map::OccupancyGrid(geometry_.width, geometry_.height, geometry_.resolution_m, geometry_.origin.x,
                                         geometry_.origin.y, thorvald_map::kFree);
  for (std::size_t i = 0; i < blocker_.size(); ++i)
    if (blocker_[i] != static_cast<std::uint8_t>(Blocker::kNone)) blocked_.data[i] = thorvald_map::kOccupied;
  blocked_distance_ = DistanceField(blocked_, params_.inflation_radius_m + geometry_.resolution_m);
  cost_.assign(blocker_.size(), 0);
  computeCosts(0, 0, geometry_.width - 1, geometry_.height - 1);
}

void Costmap::setObstacles(const std::vector<Eigen::Vector2d>& points_world) {
  if (geometry_.width == 0) return;
  constexpr auto kNone = static_cast<std::uint8_t>(Blocker::kNone),
                 kUnknown = static_cast<std::uint8_t>(Blocker::kUnknown),
                 kObstacle = static_cast<std::uint8_t>(Blocker::kObstacle);
  // The layer seen before is lifted: its cells go back to what the map says.
  std::vector<int> changed;
  for (const int i : obstacle_cells_) blocker_[i] = static_blocker_[i];
  std::vector<int> before;
  before.swap(obstacle_cells_);
  obstacle_points_ = known_points_ = 0;
  for (const auto& p : points_world) {
    if (!p.allFinite()) continue;
    const Eigen::Vector2i c = geometry_.cellOf(p);
    if (!geometry_.inside(c.x(), c.y())) continue;
    const std::size_t i = geometry_.index(c.x(), c.y());
    // Cell centres' distance: a point in a cell next to a wall cell is one cell from it however close it lies.
    if (known_distance_[i] <= params_.known_structure_tolerance_m + 1e-6) {
      ++known_points_;
      continue;
    }
    ++obstacle_points_;
    auto& b = blocker_[i];
    if (b == kNone || b == kUnknown) {
      b = kObstacle;
      obstacle_cells_.push_back(static_cast<int>(i));
    }
  }
  // Cells whose blocked state changed: the distance field and the costs within reach of them are brought up to date.
  for (const int i : before)
    if ((blocker_[i] != kNone) != (blocked_.data[i] == thorvald_map::kOccupied)) changed.push_back(i);
  for (const int i : obstacle_cells_)
    if (blocked_.data[i] != thorvald_map::kOccupied) changed.push_back(i);
  if (changed.empty()) return;
  int x0 = geometry_.width, y0 = geometry_.height, x1 = -1, y1 = -1;
  for (const int i : changed) {
    blocked_.data[i] = blocker_[i] != kNone ? thorvald_map::kOccupied : thorvald_map::kFree;
    const int x = i % geometry_.width, y = i / geometry_.width;
    x0 = std::min(x0, x), y0 = std::min(y0, y), x1 = std::max(x1, x), y1 = std::max(y1, y);
  }
  blocked_distance_.update(blocked_, nullptr, changed, {});
  const int reach = static_cast<int>(std::ceil(params_.inflation_radius_m / geometry_.resolution_m)) + 2;
  computeCosts(std::max(0, x0 - reach), std::max(0, y0 - reach), std::min(geometry_.width - 1, x1 + reach),
               std::min(geometry_.height - 1, y1 + reach));
}

void Costmap::computeCosts(int x0, int y0, int x1, int y1) {
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      const std::size_t i = geometry_.index(x, y);
      const double d = blocked_distance_.cellDistance(x, y);
      std::uint8_t c = 0;
      if (blocker_[i] != static_cast<std::uint8_t>(Blocker::kNone)) {
        c = kLethalCost;
      } else if (d <= params_.planning_radius_m) {
        c = kInscribedCost;
      } else if (d < params_.inflation_radius_m) {
        c = static_cast<std::uint8_t>(
            std::max(1.0, 252.0 * std::exp(-params_.cost_scaling * (d - params_.planning_radius_m))));
      }
      cost_[i] = c;
    }
  }
}

namespace {

// Calls visit(cx, cy) for every cell whose centre lies inside the footprint placed at `pose` (cells outside the grid
// included) until it returns true; true when it did.
template <typename Visit>
bool forFootprintCells(const thorvald_map::OccupancyGrid& geometry, const thorvald_base::Pose2D& pose,
                       const Footprint& footprint, Visit visit) {
  std::vector<Eigen::Vector2d> poly;
  Eigen::Vector2d lo(1e18, 1e18), hi(-1e18, -1e18);
  for (const auto& p : footprint.polygon) {
    poly.push_back(pose.transformPoint(p));
    lo = lo.cwiseMin(poly.back());
    hi = hi.cwiseMax(poly.back());
  }
  const Eigen::Vector2i c0 = geometry.cellOf(lo), c1 = geometry.cellOf(hi);
  for (int cy = c0.y(); cy <= c1.y(); ++cy) {
    for (int cx = c0.x(); cx <= c1.x(); ++cx) {
      const Eigen::Vector2d q = geometry.cellCentre(cx, cy);
      bool in = false;  // even-odd rule on the cell centre
      for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
        if ((poly[i].y() > q.y()) != (poly[j].y() > q.y()) &&
            q.x() < (poly[j].x() - poly[i].x()) * (q.y() - poly[i].y()) / (poly[j].y() - poly[i].y()) + poly[i].x())
          in = !in;
      }
      if (in && visit(cx, cy)) return true;
    }
  }
  return false;
}

}  // namespace

Blocker Costmap::footprintBlocker(const thorvald_base::Pose2D& pose, const Footprint& footprint) const {
  if (footprint.polygon.size() < 3 || geometry_.width == 0) return Blocker::kNone;
  Blocker found = Blocker::kNone;
  forFootprintCells(geometry_, pose, footprint, [&](int cx, int cy) {
    if (!geometry_.inside(cx, cy)) {
      found = params_.unknown_is_blocked ? Blocker::kUnknown : Blocker::kNone;
      return true;
    }
    found = blocker(cx, cy);
    return found != Blocker::kNone;
  });
  return found;
}

bool Costmap::footprintTouches(const thorvald_base::Pose2D& pose, const Footprint& footprint, Blocker which,
                               const std::vector<int>* except) const {
  if (footprint.polygon.size() < 3 || geometry_.width == 0) return false;
  const auto excepted = [except](int index) {
    return except && std::binary_search(except->begin(), except->end(), index);
  };
  return forFootprintCells(geometry_, pose, footprint, [&](int cx, int cy) {
    if (!geometry_.inside(cx, cy)) return which == Blocker::kUnknown && params_.unknown_is_blocked && !excepted(-1);
    return blocker(cx, cy) == which && !excepted(static_cast<int>(geometry_.index(cx, cy)));
  });
}

std::vector<int> Costmap::footprintCells(const thorvald_base::Pose2D& pose, const Footprint& footprint,
                                         Blocker which) const {
  std::vector<int> cells;
  if (footprint.polygon.size() < 3 || geometry_.width == 0) return cells;
  forFootprintCells(geometry_, pose, footprint, [&](int cx, int cy) {
    if (!geometry_.inside(cx, cy)) {
      if (which == Blocker::kUnknown && params_.unknown_is_blocked) cells.push_back(-1);
    } else if (blocker(cx, cy) == which) {
      cells.push_back(static_cast<int>(geometry_.index(cx, cy)));
    }
    return false;
  });
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  return cells;
}

bool turnTouches(const Costmap& costmap, const Footprint& footprint, const Eigen::Vector2d& position, double from_yaw,
                 double to_yaw, Blocker which, double step_m, const std::vector<int>* except) {
  const double turn = thorvald_base::normalizeAngle(to_yaw - from_yaw);
  const double radius = std::max(footprint.circumscribedRadius(), 1e-3);
  auto sweep = [&](double angle) {
    const int steps = std::max(1, static_cast<int>(std::ceil(std::abs(angle) * radius / std::max(step_m, 1e-3))));
    for (int k = 0; k <= steps; ++k) {
      const double yaw = from_yaw + angle * (static_cast<double>(k) / steps);
      if (costmap.footprintTouches({position.x(), position.y(), yaw}, footprint, which, except)) return true;
    }
    return false;
  };
  // Near a half turn the way the robot turns depends on which side of it the next point lies by a few centimetres:
  // both ways must be clear.
  constexpr double kEitherWay = thorvald_base::kPi - 0.35;
  return sweep(turn) || (std::abs(turn) > kEitherWay && sweep(turn - std::copysign(2.0 * thorvald_base::kPi, turn)));
}

double sweptObstacleDistance(const Costmap& costmap, const Footprint& footprint, const thorvald_base::Pose2D& pose,
                             const std::vector<Eigen::Vector2d>& path, std::size_t next_index, double ahead_m,
                             bool omnidirectional, double goal_yaw, bool reverse) {
  const double step = std::max(0.05, costmap.geometry().resolution_m);
  // A segment shorter than this is the follower's last centimetres: it closes them without turning to their heading.
  constexpr double kNoTurnBelow = 0.1;
  auto hit = [&](const Eigen::Vector2d& p, double yaw) {
    return costmap.footprintTouches({p.x(), p.y(), yaw}, footprint, Blocker::kObstacle);
  };
  auto turnHits = [&](const Eigen::Vector2d& p, double from, double to) {
    return turnTouches(costmap, footprint, p, from, to, Blocker::kObstacle, step);
  };
  const bool final_turn = std::isfinite(goal_yaw);
  const double end_yaw = final_turn ? goal_yaw : pose.yaw;
  Eigen::Vector2d prev(pose.x, pose.y);
  if (hit(prev, pose.yaw)) return 0.0;
  if (omnidirectional && turnHits(prev, pose.yaw, end_yaw)) return 0.0;
  double travelled = 0.0, heading = pose.yaw;
  for (std::size_t i = next_index; i < path.size() && travelled < ahead_m; ++i) {
    const Eigen::Vector2d seg = path[i] - prev;
    const double len = seg.norm();
    if (len < 1e-6) continue;
    if (!omnidirectional && len >= kNoTurnBelow) {
      const double seg_yaw =
          thorvald_base::normalizeAngle(std::atan2(seg.y(), seg.x()) + (reverse ? thorvald_base::kPi : 0.0));
      if (turnHits(prev, heading, seg_yaw)) return travelled;
      heading = seg_yaw;
    }
    const int steps = std::max(1, static_cast<int>(std::ceil(len / step)));
    for (int k = 1; k <= steps && travelled < ahead_m; ++k) {
      travelled += len / steps;
      const Eigen::Vector2d p = prev + seg * (static_cast<double>(k) / steps);
      if (hit(p, heading) || (omnidirectional && hit(p, end_yaw))) return travelled;
    }
    prev = path[i];
  }
  // The turn at the goal, when the check reached it.
  const bool at_end = path.size() <= next_index || (prev - path.back()).norm() < 1e-6;
  if (final_turn && at_end && travelled < ahead_m && turnHits(prev, heading, end_yaw)) return travelled;
  return -1.0;
}

thorvald_map::OccupancyGrid Costmap::toDisplayGrid() const {
  thorvald_map::OccupancyGrid g(geometry_.width, geometry_.height, geometry_.resolution_m, geometry_.origin.x,
                                geometry_.origin.y, thorvald_map::kFree);
  for (std::size_t i = 0; i < cost_.size(); ++i)
    g.data[i] = static_cast<std::int8_t>(cost_[i] >= kInscribedCost ? 100 : (cost_[i] * 98) / 252);
  return g;
}

}  // namespace thorvald_navigation
