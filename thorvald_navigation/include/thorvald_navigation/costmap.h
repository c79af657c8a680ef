#pragma once

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "thorvald_map/occupancy_grid.h"
#include "thorvald_base/pose2d.h"
#include "thorvald_navigation/distance_field.h"

namespace thorvald_navigation {

/// What makes a costmap cell impassable.
enum class Blocker : std::uint8_t { kNone = 0, kWall = 1, kUnknown = 2, kKeepOut = 3, kObstacle = 4 };
const char* blockerName(Blocker b);

/// Costs as costmap_2d writes them: 254 lethal, 253 inside the planning radius, 1..252 decaying, 0 free.
constexpr std::uint8_t kLethalCost = 254;
constexpr std::uint8_t kInscribedCost = 253;

/// The robot's outline in base_link (a polygon, counter-clockwise or not) [m].
struct Footprint {
  std::vector<Eigen::Vector2d> polygon;
  /// Largest distance from base_link to a corner [m].
  double circumscribedRadius() const;
  /// Half of the narrowest extent of the polygon's bounding box [m].
  double halfWidth() const;
  /// Empty string when the polygon is usable (>= 3 finite points with area), else why not.
  std::string check() const;
};
/// Axis-aligned rectangle around base_link [m].
Footprint rectangleFootprint(double x_min, double x_max, double y_min, double y_max);

struct CostmapParams {
  double planning_radius_m = 0.35;  ///< base_link may not come closer than this to a blocked cell [m]
  double inflation_radius_m = 1.0;  ///< cost decays to 0 at this distance [m]
  double cost_scaling = 3.0;        ///< exponential decay rate beyond planning_radius [1/m]
  bool unknown_is_blocked = true;   ///< unknown map cells block (no planning into unexplored space)
  /// Lidar points this close to a wall of the map or to the keep-out zone are that known structure (seen with the
  /// localiser's error and the map's cell size), not obstacles: the static layers already keep the robot off it [m].
  double known_structure_tolerance_m = 0.15;
  std::string validate() const;
};

/// A planning grid on the map's geometry: blocked cells from the map's walls (and unknown cells), a keep-out grid
/// (any geometry, resampled) and obstacle points, inflated for planning. Remembers what blocked each cell so a
/// refused goal can say why.
class Costmap {
 public:
  Costmap() = default;
  /// `keep_out` may be empty (width 0). Cells >= 65 of either grid block.
  Costmap(const thorvald_map::OccupancyGrid& map, const thorvald_map::OccupancyGrid& keep_out,
          const CostmapParams& params);

  /// Replaces the obstacle layer with points seen now (world frame) and re-inflates around the cells that changed
  /// (the cost of a scan is what it changed, not the map's size; equal to inflating anew, tested). Points on or
  /// within known_structure_tolerance_m of a wall of the map or of the keep-out zone are not obstacles.
  void setObstacles(const std::vector<Eigen::Vector2d>& points_world);
  /// Of the last setObstacles: points marked as obstacles, points taken as known map structure.
  std::size_t obstaclePoints() const { return obstacle_points_; }
  std::size_t knownStructurePoints() const { return known_points_; }
  const thorvald_map::OccupancyGrid& geometry() const { return geometry_; }
  std::uint8_t cost(int cx, int cy) const { return cost_[geometry_.index(cx, cy)]; }
  Blocker blocker(int cx, int cy) const { return static_cast<Blocker>(blocker_[geometry_.index(cx, cy)]); }
  /// The first blocked cell under the footprint placed at `pose`, or kNone.
  Blocker footprintBlocker(const thorvald_base::Pose2D& pose, const Footprint& footprint) const;
  /// Whether any cell under the footprint placed at `pose` is blocked by `which` (whatever else it overlaps), the
  /// cells in `except` aside (sorted grid indices; -1 stands for every cell outside the grid).
  bool footprintTouches(const thorvald_base::Pose2D& pose, const Footprint& footprint, Blocker which,
                        const std::vector<int>* except = nullptr) const;
  /// The cells under the footprint placed at `pose` that `which` blocks, as sorted grid indices (-1 first when cells
  /// outside the grid count as unknown space and the footprint reaches out of it).
  std::vector<int> footprintCells(const thorvald_base::Pose2D& pose, const Footprint& footprint, Blocker which) const;
  /// Costs as 0..100 occupancy values for display (-1 never).
  thorvald_map::OccupancyGrid toDisplayGrid() const;
  const CostmapParams& params() const { return params_; }

 private:
  /// Costs of the cells in [x0, x1] x [y0, y1] from the distance field of the blocked cells.
  void computeCosts(int x0, int y0, int x1, int y1);

  CostmapParams params_;
  thorvald_map::OccupancyGrid geometry_;
  std::vector<std::uint8_t> static_blocker_;
  std::vector<std::uint8_t> blocker_;
  std::vector<std::uint8_t> cost_;
  std::vector<float> known_distance_;    // distance to the nearest wall / keep-out cell, clamped [m]
  thorvald_map::OccupancyGrid blocked_;  // every blocked cell occupied: the sites of blocked_distance_
  DistanceField blocked_distance_;       // to the nearest blocked cell, clamped past the inflation radius
  std::vector<int> obstacle_cells_;      // cells the obstacle layer blocks now
  std::size_t obstacle_points_ = 0, known_points_ = 0;
};

/// How far along the path the robot meets a lidar obstacle [m of path; 0 at the robot]. The footprint is placed at
/// `pose`, then every 5 cm (or map cell) along path[next_index..] for the next `ahead_m` metres, and turned through
/// every rotation the robot makes on the way in steps whose arc at the footprint's farthest corner is at most 5 cm:
/// - differential: on the spot from the current heading to the first segment's, at every corner of the path from
///   one segment's heading to the next, and at the path's end to `goal_yaw` (the follower turns on the spot there;
///   where it cuts a corner with an arc instead, the arc stays inside the swept turn);
/// - omnidirectional: the heading changes from the current one to `goal_yaw` while it translates: the footprint is
///   placed at both headings at every sample, and the turn between them is swept where the robot stands and at the
///   path's end.
/// A NaN `goal_yaw` leaves the final turn out (differential) or keeps the current heading (omnidirectional);
/// `reverse`: a differential robot backs along the path (its heading opposite to the segments'). Only obstacle cells
/// count: walls, keep-out and unknown space are the planner's. Negative when the way is clear.
double sweptObstacleDistance(const Costmap& costmap, const Footprint& footprint, const thorvald_base::Pose2D& pose,
                             const std::vector<Eigen::Vector2d>& path, std::size_t next_index, double ahead_m,
                             bool omnidirectional, double goal_yaw = std::numeric_limits<double>::quiet_NaN(),
                             bool reverse = false);

/// Whether the footprint turning on the spot at `position` from `from_yaw` to `to_yaw` (the shorter way; both ways
/// for turns within 0.35 rad of a half turn) touches a cell blocked by `which`; the turn is sampled so that the
/// farthest corner moves at most `step_m` between samples; the cells in `except` aside (Costmap::footprintTouches).
bool turnTouches(const Costmap& costmap, const Footprint& footprint, const Eigen::Vector2d& position, double from_yaw,
                 double to_yaw, Blocker which, double step_m = 0.05, const std::vector<int>* except = nullptr);

}  // namespace thorvald_navigation
