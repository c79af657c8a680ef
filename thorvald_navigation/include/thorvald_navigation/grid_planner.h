#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "thorvald_navigation/costmap.h"

namespace thorvald_navigation {

struct PlannerParams {
  double cost_weight = 2.0;      ///< a cell of cost 252 counts this much extra per metre travelled through it
  int max_expansions = 2000000;  ///< bound on the search
  std::string validate() const;
};

/// The outcome of a plan request: a path of cell centres (start and goal included) or why there is none.
struct PlanResult {
  bool ok = false;
  std::vector<Eigen::Vector2d> path;  ///< world [m]
  double length_m = 0.0;
  int expansions = 0;
  std::string error;
};

/// A* on an 8-connected costmap grid. Cells at or above kInscribedCost are impassable, except that a start inside
/// them may leave by descending cost (a robot pushed close to a wall can still get out). The path is then
/// shortened by skipping points when the straight segment between them crosses no cell costlier than the cells it
/// replaces.
PlanResult planPath(const Costmap& costmap, const Eigen::Vector2d& start, const Eigen::Vector2d& goal,
                    const PlannerParams& params);

/// Length of a polyline [m].
double pathLength(const std::vector<Eigen::Vector2d>& path);

}  // namespace thorvald_navigation
