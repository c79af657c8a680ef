#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "thorvald_navigation/distance_field.h"
#include "thorvald_map/occupancy_grid.h"
#include "thorvald_base/pose2d.h"
#include "thorvald_navigation/scan_matcher.h"
#include "thorvald_map/wall_surface.h"

namespace thorvald_navigation {

/// Settings of the headland mapper; validate() names the bad one.
struct MapperParams {
  double resolution_m = 0.05;
  double initial_size_m = 20.0;       ///< side of the first grid, centred on the start; it grows as needed [m]
  double max_size_m = 400.0;          ///< bound on either side of the grid [m]
  double max_range_m = 25.0;          ///< beams longer than this only clear space up to it [m]
  double hit_log_odds = 0.85;         ///< added at a beam end
  double miss_log_odds = -0.4;        ///< added along a beam
  double clamp_log_odds = 4.0;        ///< bounds either way
  double linear_update_m = 0.1;       ///< integrate a scan when the robot moved this far... [m]
  double angular_update_rad = 0.05;   ///< ...or turned this much [rad]
  double field_max_distance_m = 0.5;  ///< reach of the distance field used to match scans [m]
  double min_inlier_fraction = 0.3;   ///< a match below this is not trusted: odometry alone places the scan
  /// Odometry prior of each match: the pose may leave the odometry prediction by about this much, plus
  /// odom_sigma_fraction of the motion since the last integrated scan. Holds the pose where the scan says little
  /// (a headland seen along its length, the start of a map that holds only part of the walls); 0: no prior [m, rad].
  double odom_sigma_xy_m = 0.01;
  double odom_sigma_yaw_rad = 0.005;
  double odom_sigma_fraction = 0.1;
  /// Match each scan to where the earlier beams ended inside the wall cells (the wall surface), each wall cell a
  /// piece of line through the mean end points around it, instead of to cell centres. At cell centres a wall seen
  /// at a grazing angle (its cells hit only here and there) is a row of dots whose bumps pull the match along the
  /// wall, scan after scan: in the MuJoCo greenhouse the map frame slid 4-6 cm along the rows in the first turn.
  /// Off in the library (its tests and mapper_bench compare both); the headland_mapper node turns it on.
  bool match_surface = false;
  /// How far each wall cell's piece of line reaches either way [m]; 0: the whole line (point-to-line distance:
  /// along a straight wall only its ends and corners fix a position, and the odometry prior holds the rest).
  double surfel_half_length_m = 0.0;
  /// A beam that meets a surface at a grazing angle runs within a cell of it for resolution / sin(angle) before its
  /// end, through the cells that hold the surface's face further along; beams of later scans end there only here
  /// and there. Clearing those cells scan after scan erased a ventilation line seen along its length beyond 3-4 m
  /// (2.5 cm cells, 0.25 deg beams). So a beam whose end lies on a straight piece of surface with its neighbours
  /// (within `grazing_neighbour_gap_m`, the middle end within a cell of their line) does not clear the cells that
  /// line passes through over the last resolution * (1 / sin(angle) - 1) of its length, where it runs within a cell
  /// of the line; the cells in front of the face it clears as before. This bounds that length [m]; 0: every beam
  /// clears every cell up to its end cell.
  double grazing_keep_max_m = 2.0;
  /// A beam without a return (nothing within range, or a surface too dark or glancing for the lidar) does not clear
  /// a cell where an earlier beam ended: it does not show that the cell is empty. In the MuJoCo greenhouse, beams
  /// from a robot 15 cm beside a ventilation line's line met the line beyond the lidar's incidence limit, returned
  /// nothing and, cleared to 25 m, erased the line's face that steeper beams had drawn.
  bool no_return_keeps_ends = true;
  double grazing_neighbour_gap_m = 2.0;  ///< neighbouring beam ends farther apart than this are no surface [m]
  ScanMatcherParams matcher;
  std::string validate() const;
};

/// What happened to one scan.
struct MapperUpdate {
  bool integrated = false;     ///< false: the robot had not moved enough, or the scan was rejected
  bool matched = false;        ///< the pose came from scan matching (else from odometry)
  thorvald_base::Pose2D pose;  ///< corrected base_link pose in the map frame
  double inlier_fraction = 0.0;
  std::string rejected;  ///< why the scan was not used (empty when it was, or when the robot stood still)
};

/// Incremental occupancy mapping with scan-to-map matching, for a headland driven once (no loop closure): each
/// scan is aligned to the map built so far starting from the odometry prediction, then traced into a log-odds
/// grid. The map frame is the pose of the first scan's odometry.
class OccupancyMapper {
 public:
  explicit OccupancyMapper(const MapperParams& params);

  /// `odom`: base_link in the odometry frame; `points_base`: beam ends in base_link [m] (hits);
  /// `free_ends_base`: ends of beams that returned nothing within range (only clear space).
  /// `sensor_base`: the sensor's origin in base_link.
  MapperUpdate addScan(const thorvald_base::Pose2D& odom, const Eigen::Vector2d& sensor_base,
                       const std::vector<Eigen::Vector2d>& points_base,
                       const std::vector<Eigen::Vector2d>& free_ends_base);

  /// The map as occupancy values (0 free, 100 occupied, -1 unknown), cropped to the observed area.
  thorvald_map::OccupancyGrid occupancyGrid() const;
  /// Where the beams ended inside each cell of occupancyGrid() (same crop): the walls' sub-cell surface.
  thorvald_map::WallSurface wallSurface() const;
  int scansUsed() const { return scans_used_; }
  /// Area observed as free or occupied [m^2].
  double knownAreaM2() const;
  /// map -> odom correction [pose of the odom frame in the map frame].
  thorvald_base::Pose2D mapToOdom() const { return map_to_odom_; }

 private:
  void ensureInside(const Eigen::Vector2d& p);
  /// Cells of the observed area plus a margin: x0, y0, x1, y1 (inclusive); x1 < 0 when nothing was observed.
  Eigen::Vector4i observedBounds() const;
  /// Traces one scan into the grid: hits first, then the free space of every beam.
  void insert(const thorvald_base::Pose2D& pose, const Eigen::Vector2d& sensor_base,
              const std::vector<Eigen::Vector2d>& points_base, const std::vector<Eigen::Vector2d>& free_ends_base);
  /// The surface a beam ends on, where it meets it at a grazing angle (MapperParams::grazing_keep_max_m): from
  /// `from_t` on (a fraction of the beam), the cells the surface's line passes through are not cleared.
  struct GrazedFace {
    double from_t = 2.0;  ///< beyond the beam's end: no such stretch
    Eigen::Vector2d point = Eigen::Vector2d::Zero(), normal = Eigen::Vector2d::UnitY();
    /// True when the line crosses the square cell of side `res` centred at `c`.
    bool crosses(const Eigen::Vector2d& c, double res) const {
      return std::abs(normal.dot(c - point)) <= 0.5 * res * (1.0 + std::abs(normal.x()) + std::abs(normal.y()));
    }
  };
  /// The face that hit i's beam grazes, from its neighbouring ends (`hits` in beam order, map frame).
  GrazedFace grazedFace(const Eigen::Vector2d& origin, const std::vector<Eigen::Vector2d>& hits, std::size_t i) const;
  /// Clears the cells from `from` to `to`, except the cells of `face`'s line on its stretch (a default GrazedFace has
  /// none). A beam that met something ends at `to` (its cell is not cleared); a beam without a return (`no_return`)
  /// clears `to`'s cell too, but no cell where earlier beams ended (MapperParams::no_return_keeps_ends).
  void traceFree(const Eigen::Vector2d& from, const Eigen::Vector2d& to, bool no_return, const GrazedFace& face);
  /// True when no_return_keeps_ends is on and some earlier beam ended in cell c.
  bool holdsEnds(const Eigen::Vector2i& c) const;
  /// Adds log-odds to a cell unless this scan already updated it; false when it did not.
  bool update(const Eigen::Vector2i& c, double log_odds);

  MapperParams params_;
  std::vector<float> log_odds_;
  thorvald_map::OccupancyGrid
      occupancy_;                      ///< occupancy values of log_odds_ (same geometry), kept up to date cell by cell
  thorvald_map::WallSurface surface_;  ///< per cell of log_odds_: mean beam end and count
  std::vector<std::uint32_t> scan_stamp_;  ///< per cell: the scan that last updated it
  std::uint32_t scan_counter_ = 0;
  thorvald_map::OccupancyGrid geometry_;  ///< size and origin of log_odds_ (its data is unused)
  /// The matching field: the cropped grid's walls at their cell centres, rebuilt for every scan.
  DistanceField field_;
  std::vector<int> touched_;  ///< cells updated by the scan being inserted
  bool first_ = true;
  thorvald_base::Pose2D map_to_odom_;
  thorvald_base::Pose2D last_integrated_odom_;
  int scans_used_ = 0;
};

}  // namespace thorvald_navigation
