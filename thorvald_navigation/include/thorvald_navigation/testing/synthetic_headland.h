#pragma once

#include <cstdint>
#include <random>
#include <vector>

#include <Eigen/Core>

#include "thorvald_map/occupancy_grid.h"
#include "thorvald_base/pose2d.h"

namespace thorvald_navigation {
namespace testing {

/// A wall segment [m].
struct Segment {
  Eigen::Vector2d a, b;
};

/// Options of the synthetic greenhouse headland.
struct HeadlandOptions {
  double length_m = 16.0;      ///< along the headland (x)
  double depth_m = 5.0;        ///< headland floor depth (y), rows start at y = depth
  double row_spacing_m = 1.6;  ///< rail-set spacing along x
  double row_length_m = 3.0;   ///< how far each row (plant/pipe line pair) is drawn into the greenhouse
  int clutter_boxes = 3;       ///< random boxes on the floor (seeded), between y = 0.6 m and depth - 1.5 m
  double box_size_m = 0.4;
  std::uint32_t seed = 1;
};

/// A headland: outer walls, rows of plants starting at its far edge (two lines per rail set), random boxes.
/// Exact ray casting for scans, rasterisation for the truth map.
class SyntheticHeadland {
 public:
  explicit SyntheticHeadland(const HeadlandOptions& options);

  const std::vector<Segment>& segments() const { return segments_; }
  const HeadlandOptions& options() const { return options_; }
  /// Distance along a ray to the nearest segment, or `max_range` [m].
  double castRay(const Eigen::Vector2d& origin, double angle_rad, double max_range) const;
  /// Beam end points in base_link of a scan from `pose` (sensor at `sensor_base`, same heading as base_link), with
  /// Gaussian range noise; beams that hit nothing within `max_range` are left out.
  std::vector<Eigen::Vector2d> scan(const thorvald_base::Pose2D& pose, const Eigen::Vector2d& sensor_base, int beams,
                                    double angle_min, double angle_max, double max_range, double noise_m,
                                    std::mt19937* rng) const;
  /// Occupancy grid: segments rasterised as occupied, inside the outer wall free, outside unknown.
  thorvald_map::OccupancyGrid truthMap(double resolution_m) const;
  /// Adds a square obstacle (e.g. a person) of side `size_m` centred at `c`.
  void addBox(const Eigen::Vector2d& c, double size_m);

 private:
  HeadlandOptions options_;
  std::vector<Segment> segments_;
};

}  // namespace testing
}  // namespace thorvald_navigation
