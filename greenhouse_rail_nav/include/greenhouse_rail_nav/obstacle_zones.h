#pragma once

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "thorvald_map/occupancy_grid.h"

namespace greenhouse_rail_nav {

/// The protected zone around the UV robot and how lidar points are grouped (issue 29). Lengths in base_link [m].
struct ZoneParams {
  double cluster_gap_m = 0.2;        ///< neighbouring scan points closer than this belong to one cluster
  int min_cluster_points = 3;        ///< fewer points: noise, ignored
  double person_min_width_m = 0.25;  ///< a cluster this wide across the beams ...
  double person_max_width_m = 0.9;   ///< ... up to this is a person's size
  /// ... and a circle fits its points (a round body, not a trolley's or a crate's flat face or corner): the fitted arc
  /// bulges towards the lidar this far from its chord [m] ...
  double person_min_depth_m = 0.05;
  /// ... with this RMS distance of its points from the circle at most, the points farther than
  /// person_fit_outlier_m from it (mixed pixels at the edges, noise spikes) left out [m] ...
  double person_max_fit_rms_m = 0.02;
  double person_fit_outlier_m = 0.05;
  double person_min_inliers = 0.8;  ///< ... and at least this share of its points within person_fit_outlier_m of it
  /// Near the robot (not in the row), a person counts once seen in this many consecutive scans within
  /// person_confirm_radius_m of where they were: a lidar plane that pitches onto a low tube for one scan is nobody
  int person_confirm_scans = 3;
  double person_confirm_radius_m = 0.3;  ///< [m]
  /// Headland: a person (cluster not in the map) within this of base_link is in the zone (the lamps' radius) [m].
  double headland_radius_m = 1.5;
  double map_clearance_m = 0.2;  ///< headland: a point this close to an occupied map cell is the map [m]
  /// Row: the corridor watched between the rails, |y| below this, ahead of the robot [m]. Wider than the rails'
  /// corridor (0.3 m, the pipes' outer flanks) by a guard: a body standing at its side shows the lidar only its grazing
  /// edge, where the beams are 4 cm apart at 9 m (with this at 0.3 m a person 1-3 cm into the rails' corridor at 9 m
  /// went unseen for 1.3 s in the simulator).
  double row_half_width_m = 0.35;
  /// Row: points up to this beyond the corridor's sides join its clusters, and a cluster of min_cluster_points
  /// points with one of them inside the corridor is in it: a body stepping in is seen as its edge crosses the side,
  /// not once min_cluster_points of its returns are inside (at 10 m the beams are 4 cm apart: ~10 cm in) [m]; 0:
  /// only the points inside count.
  double row_edge_band_m = 0.2;
  /// Row: a person outside the corridor (in a plant row beside the robot, behind it at the rails' start) whose
  /// estimated centre (cluster centroid plus half its width) is within this of base_link is in the lamps' reach and
  /// in the zone, once confirmed over person_confirm_scans scans as near the robot on the headland [m]; 0: off.
  double row_lamps_radius_m = 1.5;
  /// Treating: nobody beside the corridor is watched within this of the rails' start or the row's end (along the row):
  /// the lines along the rows (ventilation ducts) end there in round caps that a lidar grazing their top takes for a
  /// person [m].
  double row_ends_margin_m = 0.6;
  /// Row: a return at the set's length less this (or beyond) is the far end; anything shorter is an obstacle [m].
  double end_tolerance_m = 1.0;
  double row_ahead_m = 100.0;  ///< row: obstacles farther ahead than this are not in the zone [m]
  /// Row: a run of consecutive returns (gaps below structure_gap_m) straight within structure_tolerance_m, at least
  /// this long and within structure_max_angle_rad of the robot's heading, is a line the greenhouse runs along the
  /// rows (a heating or ventilation line, a plant row's edge) and no obstacle: a robot turned a few degrees on the
  /// rails sees such a line cross its corridor ahead. Nobody is a straight line this long [m]; 0: off.
  double structure_min_length_m = 2.5;
  double structure_tolerance_m = 0.06;    ///< [m]
  double structure_gap_m = 0.6;           ///< [m]
  double structure_max_angle_rad = 0.35;  ///< [rad]
  double end_half_angle_rad = 0.05;  ///< the far end's range: median of the returns within this of the lidar's axis
  double rear_stop_range_m = 1.0;    ///< reversing: a rear range finder reading less is something behind [m]
  /// Reversing with the rest of the way known (ZoneContext::reverse_left_m): something behind holds the robot only
  /// when nearer than that rest plus this clearance (and nearer than rear_stop_range_m), so a trolley parked just
  /// behind where the robot stops does not hold it for good [m].
  double rear_clearance_m = 0.3;
  /// Reversing for an alignment's run-up on the headland: something behind that holds the robot this long ends the
  /// step where the robot stands, short of its length, instead of holding it for good (a trolley parked behind the
  /// target pose); the alignment goes on from there, and gives the set up after its attempts. Backing off or out of
  /// the rails always waits [s]; 0: always wait.
  double behind_wait_s = 20.0;
  double clear_time_s = 2.0;  ///< the zone must be clear this long before the mission resumes [s]

  std::string validate() const;
};

/// A lidar return in base_link [m].
struct ScanPoint {
  double x = 0.0, y = 0.0;
};

/// Neighbouring returns that belong to one body.
struct PointCluster {
  double x = 0.0, y = 0.0;  ///< centroid in base_link [m]
  double near_x = 0.0;      ///< smallest x of its points [m]
  double inner_y = 0.0;     ///< smallest |y| of its points [m]
  double width = 0.0;       ///< across the lidar's beams [m]
  /// Round-body fit (person_* parameters): the circle through its points without the outliers; depth is the fitted
  /// arc's bulge from its chord, towards the lidar (0 when the circle's centre is on the lidar's side: a concave shape)
  double depth = 0.0;        ///< [m]
  double fit_radius = 0.0;   ///< [m]
  double fit_rms = 0.0;      ///< of the inliers [m]
  double fit_inliers = 0.0;  ///< share of the points within person_fit_outlier_m of the circle
  int points = 0;
  bool person = false;  ///< of a person's size and shape
  /// Row: a person beside the corridor within row_lamps_radius_m (in the zone once PersonConfirmation confirms it)
  bool beside = false;
};

/// Groups points given in scan order: a point joins the cluster of the one before it when closer than
/// cluster_gap_m. Clusters of fewer than min_cluster_points are dropped. A cluster's width is measured across the
/// beams of a lidar at (origin_x, 0) (the angle it spans times its mean range), so that a streak of mixed pixels
/// along the beams at an edge is not taken for a body. A cluster of a person's width is a person when a circle fits
/// it (fitRoundBody); with fewer than kMinFitPoints points its shape cannot be told and it counts as one.
constexpr int kMinFitPoints = 5;

/// Fits a circle to `pts` (algebraic least squares, twice more without the points farther than person_fit_outlier_m
/// from the last circle) and fills c's depth and fit_* fields; the lidar at (origin_x, 0). Returns whether the fit
/// shows a round body bulging towards the lidar: RMS, inlier share and depth within the person_* parameters.
bool fitRoundBody(const std::vector<ScanPoint>& pts, const ZoneParams& p, double origin_x, PointCluster* c);

std::vector<PointCluster> clusterScan(const std::vector<ScanPoint>& points, const ZoneParams& p, double origin_x = 0.0);

/// Per point of `points` (scan order, base_link): whether it belongs to a line the greenhouse runs along the rows
/// (ZoneParams::structure_*).
std::vector<bool> rowStructure(const std::vector<ScanPoint>& points, const ZoneParams& p);

/// What the mission is doing, which decides the zone.
enum class ZonePhase {
  kIdle,      ///< not moving for the mission: people within the headland radius only (for the interlock)
  kHeadland,  ///< on the headland floor: people (not in the map) within the headland radius
  kRow,       ///< entering or on the rails: anything in the corridor between the rails short of the set's end
  kReverse,   ///< reversing: the rear range finders
};
const char* toString(ZonePhase phase);

struct ZoneContext {
  ZonePhase phase = ZonePhase::kIdle;
  /// Row: distance along base_link's x to the rail set's far end (the set's length less how far base_link is along
  /// it) [m]; <= 0: unknown, and every return ahead counts as the far end (no row obstacles).
  double row_end_m = 0.0;
  /// Reverse: how much farther the robot reverses at most (to its stored pose, plus what it may go on to find the
  /// floor) [m]; < 0: unknown (rear_stop_range_m alone decides).
  double reverse_left_m = -1.0;
  /// Row: the robot is treating, its lamps lit or about to be: people beside the corridor within row_lamps_radius_m
  /// count (entering the rails the lamps are off, and the rows' structure beside the rails' start is no one).
  bool lamps = false;
  /// Row: how far base_link is past the rails' start [m]; < 0: unknown.
  double row_along_m = -1.0;
};

/// The zone at one scan.
struct ZoneVerdict {
  bool blocked = false;  ///< something in the protected zone
  bool person = false;   ///< a person-sized cluster in it
  bool behind = false;   ///< reversing: the rear range finders see something
  std::string why;       ///< what and where, for the status and the log (empty when clear)
  /// Row: the lidar's range to the far end where it agrees with the set's length; NaN when nothing is seen ahead or
  /// what is seen is short of the end (an obstacle) [m].
  double end_range_m = std::numeric_limits<double>::quiet_NaN();
  std::vector<PointCluster> clusters;  ///< every cluster considered (for markers)
  std::vector<bool> in_zone;           ///< per cluster
};

/// True for a point of the known map (walls, plant rows) at base_link coordinates.
using KnownPoint = std::function<bool(double x, double y)>;

/// Whether a point of the map frame is not free headland, so nobody the headland zone must watch for: outside `map`,
/// on an unknown cell, within `reach_cells` of an occupied cell (>= 50), or on an occupied cell (>= 65) of
/// `keep_out` (the map analyzer's zone beyond the headland edge: the rows, with their plants, heating and
/// ventilation lines; an empty grid: none).
bool notHeadland(const thorvald_map::OccupancyGrid& map, const thorvald_map::OccupancyGrid& keep_out, int reach_cells,
                 const Eigen::Vector2d& p_map);

/// Evaluates one scan: `points` in base_link in scan order, `lidar_x` the lidar's position on base_link's x axis
/// [m], `known` the map on the headland (may be empty: nothing is known). The rear range finders' readings (NaN or
/// out of range: nothing) count in the reverse phase only.
ZoneVerdict evaluateZone(const std::vector<ScanPoint>& points, double lidar_x, const ZoneContext& ctx,
                         const ZoneParams& p, const KnownPoint& known = {},
                         const std::vector<double>& rear_ranges = {});

/// Confirms the people near the robot (headland, idle, reverse; in the row the people beside the corridor, while
/// anything in the corridor short of the end blocks at once) over consecutive scans: a person cluster in the zone
/// stays in it only when person clusters were in the zone within person_confirm_radius_m of it in each of the
/// person_confirm_scans - 1 scans before. In the row a confirmed person beside the robot blocks it.
class PersonConfirmation {
 public:
  explicit PersonConfirmation(const ZoneParams& p)
      : scans_(p.person_confirm_scans), radius_m_(p.person_confirm_radius_m) {}
  /// Takes the latest scan's verdict in `phase`: clears the people not yet confirmed and the block they made.
  void apply(ZonePhase phase, ZoneVerdict* v);

 private:
  static void confirmRowPerson(const PointCluster& c, ZoneVerdict* v);
  int scans_;
  double radius_m_;
  std::vector<std::vector<ScanPoint>> seen_;  ///< people in the zone in the latest scans, oldest first
};

/// Follows a zone over time: blocked at once, clear only after clear_time_s without anything in it.
class ZoneHold {
 public:
  explicit ZoneHold(double clear_time_s) : clear_time_s_(clear_time_s) {}
  /// One verdict at time t [s]; returns whether the mission must hold.
  bool update(bool blocked, double t_s);
  bool holding() const { return holding_; }

 private:
  double clear_time_s_;
  bool holding_ = false;
  double last_blocked_s_ = -1e18;
};

}  // namespace greenhouse_rail_nav
