#include "cotton_harvester/control/row_turn_planner.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace cotton_harvester {
namespace control {

namespace {

/// Waypoints in the leaving row's frame (x out of the row from its end, y left), built arc by arc.
class TurnBuilder {
 public:
  explicit TurnBuilder(double step_m) : step_m_(step_m) {}

  void lineTo(const Eigen::Vector2d& to) {
    const Eigen::Vector2d from = points_.empty() ? Eigen::Vector2d::Zero() : points_.back();
    const int n = std::max(1, static_cast<int>(std::ceil((to - from).norm() / step_m_)));
    for (int i = points_.empty() ? 0 : 1; i <= n; ++i) points_.push_back(from + (to - from) * i / n);
  }
  /// Arc around `centre` with radius r from angle a0 to a1 [rad] (a1 < a0: clockwise).
  void arc(const Eigen::Vector2d& centre, double r, double a0, double a1) {
    const int n = std::max(1, static_cast<int>(std::ceil(std::abs(a1 - a0) * r / step_m_)));
    for (int i = 1; i <= n; ++i) {
      const double a = a0 + (a1 - a0) * i / n;
      points_.push_back(centre + r * Eigen::Vector2d(std::cos(a), std::sin(a)));
    }
  }
  std::vector<Eigen::Vector2d>& points() { return points_; }

 private:
  double step_m_;
  std::vector<Eigen::Vector2d> points_;
};

/// Turn to the left (the next row at lateral d > 0) in the local frame, leaving from (exit, 0) heading +x.
void leftTurn(double d, double r, double exit, TurnBuilder* b) {
  const Eigen::Vector2d o(exit, 0.0);
  if (d >= 2.0 * r) {
    b->arc(o + Eigen::Vector2d(0, r), r, -M_PI_2, 0.0);
    b->lineTo(o + Eigen::Vector2d(r, d - r));
    b->arc(o + Eigen::Vector2d(0, d - r), r, 0.0, M_PI_2);
    return;
  }
  // Omega: right arc around c1, left arc around c2 (touching both), right arc around c3 into the row.
  const Eigen::Vector2d c1 = o + Eigen::Vector2d(0, -r), c3 = o + Eigen::Vector2d(0, d + r);
  const double half = 0.5 * (d + 2.0 * r);
  const Eigen::Vector2d c2 = o + Eigen::Vector2d(std::sqrt(4.0 * r * r - half * half), 0.5 * d);
  const double phi = std::atan2(c2.y() - c1.y(), c2.x() - c1.x());
  b->arc(c1, r, M_PI_2, phi);
  b->arc(c2, r, phi - M_PI, M_PI - phi);
  b->arc(c3, r, -phi, -M_PI_2);
}

}  // namespace

std::string RowTurnParams::check() const {
  if (!(turn_radius_m > 0.0)) return "turn_radius_m: expected > 0";
  if (!(straight_m >= 0.0)) return "straight_m: expected >= 0";
  if (!(waypoint_step_m > 0.0 && waypoint_step_m <= turn_radius_m)) return "waypoint_step_m: expected in (0, R]";
  return "";
}

int rowsOverForUTurn(double row_spacing_m, double turn_radius_m) {
  if (!(row_spacing_m > 0.0) || !(turn_radius_m > 0.0))
    throw std::invalid_argument("rowsOverForUTurn: spacing and radius must be > 0");
  return std::max(1, static_cast<int>(std::ceil(2.0 * turn_radius_m / row_spacing_m - 1e-9)));
}

RowTurn planRowTurn(const Eigen::Vector2d& from, double heading_rad, double lateral_m, const RowTurnParams& params) {
  if (const std::string bad = params.check(); !bad.empty()) throw std::invalid_argument("row turn: " + bad);
  if (!(std::abs(lateral_m) > 1e-6) || !std::isfinite(lateral_m))
    throw std::invalid_argument("row turn: lateral_m: expected != 0, got " + std::to_string(lateral_m));
  if (!from.allFinite() || !std::isfinite(heading_rad)) throw std::invalid_argument("row turn: pose not finite");
  const double d = std::abs(lateral_m), r = params.turn_radius_m;
  TurnBuilder b(params.waypoint_step_m);
  b.lineTo(Eigen::Vector2d(params.straight_m, 0.0));
  leftTurn(d, r, params.straight_m, &b);
  b.lineTo(Eigen::Vector2d(0.0, d));  // back along the next row's line to its end
  RowTurn turn;
  turn.shape = d >= 2.0 * r ? TurnShape::kU : TurnShape::kOmega;
  const double side = lateral_m > 0.0 ? 1.0 : -1.0;
  turn.min_lateral_m = std::numeric_limits<double>::infinity();
  turn.max_lateral_m = -std::numeric_limits<double>::infinity();
  const double c = std::cos(heading_rad), s = std::sin(heading_rad);
  for (Eigen::Vector2d p : b.points()) {
    p.y() *= side;  // a turn to the right is the left one mirrored
    turn.depth_m = std::max(turn.depth_m, p.x());
    turn.min_lateral_m = std::min(turn.min_lateral_m, p.y());
    turn.max_lateral_m = std::max(turn.max_lateral_m, p.y());
    turn.waypoints.push_back(from + Eigen::Vector2d(c * p.x() - s * p.y(), s * p.x() + c * p.y()));
  }
  return turn;
}

}  // namespace control
}  // namespace cotton_harvester
