#include "thorvald_navigation/grid_planner.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

namespace thorvald_navigation {

std::string PlannerParams::validate() const {
  if (!(cost_weight >= 0.0) || !std::isfinite(cost_weight)) return "cost_weight must be >= 0";
  if (max_expansions < 100) return "max_expansions must be >= 100";
  return {};
}

double pathLength(const std::vector<Eigen::Vector2d>& path) {
  double l = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) l += (path[i] - path[i - 1]).norm();
  return l;
}

namespace {

// Highest cost of the cells a straight segment visits (sampled at a quarter cell).
int segmentMaxCost(const Costmap& cm, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const auto& g = cm.geometry();
  const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / (0.25 * g.resolution_m))));
  int worst = 0;
  for (int i = 0; i <= steps; ++i) {
    const Eigen::Vector2i c = g.cellOf(a + (b - a) * (static_cast<double>(i) / steps));
    if (!g.inside(c.x(), c.y())) return kLethalCost;
    worst = std::max(worst, static_cast<int>(cm.cost(c.x(), c.y())));
  }
  return worst;
}

std::vector<Eigen::Vector2d> shorten(const Costmap& cm, const std::vector<Eigen::Vector2d>& path) {
  if (path.size() < 3) return path;
  std::vector<Eigen::Vector2d> out{path.front()};
  std::size_t i = 0;
  while (i + 1 < path.size()) {
    // The worst cost of the cells the grid path visits between i and j, versus the straight segment.
    std::size_t best = i + 1;
    int grid_worst = 0;
    for (std::size_t j = i + 1; j < path.size() && (path[j] - path[i]).norm() < 5.0; ++j) {
      const Eigen::Vector2i c = cm.geometry().cellOf(path[j]);
      grid_worst = std::max(grid_worst, static_cast<int>(cm.cost(c.x(), c.y())));
      if (segmentMaxCost(cm, path[i], path[j]) <= grid_worst) best = j;
    }
    out.push_back(path[best]);
    i = best;
  }
  return out;
}

}  // namespace

PlanResult planPath(const Costmap& costmap, const Eigen::Vector2d& start, const Eigen::Vector2d& goal,
                    const PlannerParams& params) {
  PlanResult r;
  const thorvald_map::OccupancyGrid& g = costmap.geometry();
  if (!start.allFinite() || !goal.allFinite()) {
    r.error = "start or goal is not finite";
    return r;
  }
  const Eigen::Vector2i s = g.cellOf(start), t = g.cellOf(goal);
  if (!g.inside(s.x(), s.y())) {
    r.error = "start is outside the map";
    return r;
  }
  if (!g.inside(t.x(), t.y())) {
    r.error = "goal is outside the map";
    return r;
  }
  if (costmap.cost(t.x(), t.y()) >= kInscribedCost) {
    const Blocker b = costmap.blocker(t.x(), t.y());
    r.error = b != Blocker::kNone ? std::string("goal is in ") + blockerName(b)
                                  : "goal is within the planning radius of a blocked cell";
    return r;
  }
  const std::size_t n = static_cast<std::size_t>(g.width) * g.height;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<double> dist(n, kInf);
  std::vector<int> parent(n, -1);
  std::vector<char> closed(n, 0);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> open;
  const int start_i = static_cast<int>(g.index(s.x(), s.y())), goal_i = static_cast<int>(g.index(t.x(), t.y()));
  auto h = [&](int x, int y) { return std::hypot(x - t.x(), y - t.y()) * g.resolution_m; };
  dist[start_i] = 0.0;
  open.push({h(s.x(), s.y()), start_i});
  static const int kDx[8] = {1, -1, 0, 0, 1, 1, -1, -1};
  static const int kDy[8] = {0, 0, 1, -1, 1, -1, 1, -1};
  while (!open.empty()) {
    const int cur = open.top().second;
    open.pop();
    if (closed[cur]) continue;
    closed[cur] = 1;
    if (cur == goal_i) break;
    if (++r.expansions > params.max_expansions) {
      r.error = "search exceeded max_expansions";
      return r;
    }
    const int cx = cur % g.width, cy = cur / g.width;
    const int cur_cost = costmap.cost(cx, cy);
    for (int k = 0; k < 8; ++k) {
      const int nx = cx + kDx[k], ny = cy + kDy[k];
      if (!g.inside(nx, ny)) continue;
      const int ni = static_cast<int>(g.index(nx, ny));
      if (closed[ni]) continue;
      const int c = costmap.cost(nx, ny);
      if (c == kLethalCost) continue;
      // Inside the planning radius only while escaping from a start there, and only downhill.
      if (c >= kInscribedCost && !(cur_cost >= kInscribedCost && c <= cur_cost)) continue;
      const double step = (k < 4 ? 1.0 : std::sqrt(2.0)) * g.resolution_m;
      const double nd = dist[cur] + step * (1.0 + params.cost_weight * std::min(c, 252) / 252.0);
      if (nd < dist[ni]) {
        dist[ni] = nd;
        parent[ni] = cur;
        open.push({nd + h(nx, ny), ni});
      }
    }
  }
  if (!closed[goal_i]) {
    r.error = "no collision-free path from start to goal";
    return r;
  }
  std::vector<Eigen::Vector2d> cells;
  for (int i = goal_i; i != -1; i = parent[i]) cells.push_back(g.cellCentre(i % g.width, i / g.width));
  std::reverse(cells.begin(), cells.end());
  cells.front() = start;
  cells.back() = goal;
  r.path = shorten(costmap, cells);
  r.length_m = pathLength(r.path);
  r.ok = true;
  return r;
}

}  // namespace thorvald_navigation
