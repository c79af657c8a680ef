#pragma once

#include <string>
#include <vector>

namespace greenhouse_rail_nav {

/// What a down-facing range finder sees under it.
enum class Surface { kUnknown, kFloor, kRail, kEdge };

const char* surfaceName(Surface s);

/// Geometry of the down-facing range finders (greenhouse paper §IV-2): on the headland floor they read their
/// mounting height above the floor; over a rail they read the distance to the pipe top (the pipe top lies
/// `rail_height_m` above the floor); past the edge of the headland floor they read more than the floor
/// (the rows' ground lies lower) or nothing at all.
struct SurfaceClassifierParams {
  double floor_range_m = 0.35;   ///< reading over the headland floor [m]
  double rail_height_m = 0.055;  ///< pipe top above the headland floor [m]
  double tolerance_m = 0.02;     ///< a reading within this of the floor or rail reading counts as that [m]
  double edge_margin_m = 0.05;   ///< a reading farther than floor + this (or no return) is an edge [m]
  int confirm_readings = 3;      ///< consecutive agreeing readings before a sensor's surface changes

  /// Empty when the parameters are consistent, else what is wrong.
  std::string validate() const;
};

/// Classifies one reading. `range_m` may be +inf (no return: an edge) or NaN (a broken reading: unknown).
Surface classifyRange(double range_m, const SurfaceClassifierParams& p);

/// Debounced per-sensor classification: a sensor's reported surface changes only after `confirm_readings`
/// consecutive readings agree, except an edge, which is reported at once (safety first).
class SurfaceTracker {
 public:
  SurfaceTracker(const SurfaceClassifierParams& p, std::size_t sensors);
  /// Feeds one reading of sensor `index`; returns its (debounced) surface.
  Surface update(std::size_t index, double range_m);
  Surface surface(std::size_t index) const { return state_.at(index).reported; }
  std::size_t size() const { return state_.size(); }
  /// The common surface of the given sensors: the one they all report, kEdge if any reports an edge,
  /// else kUnknown (a transition in progress or disagreement).
  Surface common(const std::vector<std::size_t>& indices) const;

 private:
  struct SensorState {
    Surface reported = Surface::kUnknown;
    Surface candidate = Surface::kUnknown;
    int count = 0;
  };
  SurfaceClassifierParams params_;
  std::vector<SensorState> state_;
};

}  // namespace greenhouse_rail_nav
