#include "greenhouse_rail_nav/surface_classifier.h"

#include <cmath>
#include <sstream>

namespace greenhouse_rail_nav {

const char* surfaceName(Surface s) {
  switch (s) {
    case Surface::kFloor:
      return "floor";
    case Surface::kRail:
      return "rail";
    case Surface::kEdge:
      return "edge";
    default:
      return "unknown";
  }
}

std::string SurfaceClassifierParams::validate() const {
  std::ostringstream e;
  if (!(floor_range_m > 0.0 && std::isfinite(floor_range_m))) e << "floor_range must be > 0 [m]; ";
  if (!(rail_height_m > 0.0 && rail_height_m < floor_range_m)) e << "rail_height must be in (0, floor_range) [m]; ";
  if (!(tolerance_m > 0.0)) e << "tolerance must be > 0 [m]; ";
  if (!(2.0 * tolerance_m < rail_height_m))
    e << "tolerance (" << tolerance_m << ") must be below half the rail height (" << rail_height_m
      << ") or floor and rail cannot be told apart; ";
  if (!(edge_margin_m > tolerance_m)) e << "edge_margin must exceed tolerance [m]; ";
  if (confirm_readings < 1) e << "confirm_readings must be at least 1; ";
  return e.str();
}

Surface classifyRange(double range_m, const SurfaceClassifierParams& p) {
  if (std::isnan(range_m)) return Surface::kUnknown;
  if (range_m > p.floor_range_m + p.edge_margin_m) return Surface::kEdge;  // includes +inf (no return)
  if (std::fabs(range_m - p.floor_range_m) <= p.tolerance_m) return Surface::kFloor;
  if (std::fabs(range_m - (p.floor_range_m - p.rail_height_m)) <= p.tolerance_m) return Surface::kRail;
  return Surface::kUnknown;
}

SurfaceTracker::SurfaceTracker(const SurfaceClassifierParams& p, std::size_t sensors) : params_(p), state_(sensors) {}

Surface SurfaceTracker::update(std::size_t index, double range_m) {
  SensorState& s = state_.at(index);
  const Surface now = classifyRange(range_m, params_);
  if (now == Surface::kEdge) {
    s.reported = s.candidate = Surface::kEdge;
    s.count = params_.confirm_readings;
    return s.reported;
  }
  if (now == s.candidate) {
    ++s.count;
  } else {
    s.candidate = now;
    s.count = 1;
  }
  if (s.count >= params_.confirm_readings) s.reported = s.candidate;
  return s.reported;
}

Surface SurfaceTracker::common(const std::vector<std::size_t>& indices) const {
  if (indices.empty()) return Surface::kUnknown;
  const Surface first = state_.at(indices.front()).reported;
  bool same = true;
  for (std::size_t i : indices) {
    const Surface s = state_.at(i).reported;
    if (s == Surface::kEdge) return Surface::kEdge;
    same = same && s == first;
  }
  return same ? first : Surface::kUnknown;
}

}  // namespace greenhouse_rail_nav
