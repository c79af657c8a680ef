#include "greenhouse_rail_nav/rail_alignment.h"

#include <cmath>
#include <sstream>

namespace greenhouse_rail_nav {

std::string AlignmentParams::validate() const {
  std::ostringstream e;
  if (!std::isfinite(approach_x_m) || approach_x_m >= 0.0) e << "approach_x must be < 0 (in front of the rails) [m]; ";
  if (!(max_turn_rad > 0.05 && max_turn_rad < 1.5)) e << "max_turn must be in (0.05, 1.5) [rad]; ";
  if (!(run_up_m > 0.0 && run_up_m <= 5.0)) e << "run_up must be in (0, 5] [m]; ";
  if (!(y_limit_m > 0.0)) e << "y_limit must be > 0 [m]; ";
  if (!(yaw_limit_rad > 0.0)) e << "yaw_limit must be > 0 [rad]; ";
  if (!(x_window_m > 0.0)) e << "x_window must be > 0 [m]; ";
  if (!(min_step_m >= 0.0 && min_step_m < y_limit_m)) e << "min_step must be in [0, y_limit) [m]; ";
  if (!(min_rotation_rad >= 0.0 && min_rotation_rad < yaw_limit_rad))
    e << "min_rotation must be in [0, yaw_limit) [rad]; ";
  return e.str();
}

bool withinEntryLimits(const thorvald_base::Pose2D& r, bool x_observed, const AlignmentParams& p) {
  if (!std::isfinite(r.x) || !std::isfinite(r.y) || !std::isfinite(r.yaw)) return false;
  if (std::fabs(r.y) > p.y_limit_m || std::fabs(thorvald_base::normalizeAngle(r.yaw)) > p.yaw_limit_rad) return false;
  return !x_observed || std::fabs(r.x - p.approach_x_m) <= p.x_window_m;
}

namespace {
void addRotation(std::vector<MotionStep>* plan, double angle, const AlignmentParams& p, const char* label) {
  if (std::fabs(angle) >= p.min_rotation_rad) plan->push_back({MotionStep::Kind::kRotate, angle, label});
}
void addTranslation(std::vector<MotionStep>* plan, double d, const AlignmentParams& p, const char* label) {
  if (std::fabs(d) >= p.min_step_m) plan->push_back({MotionStep::Kind::kTranslate, d, label});
}
}  // namespace

std::vector<MotionStep> planAlignment(const thorvald_base::Pose2D& r, const AlignmentParams& p) {
  std::vector<MotionStep> plan;
  if (!std::isfinite(r.x) || !std::isfinite(r.y) || !std::isfinite(r.yaw)) return plan;
  addRotation(&plan, -thorvald_base::normalizeAngle(r.yaw), p, "rotate to align");
  const double xt = p.approach_x_m;
  // Driving diagonally towards the centre line from run_up before the approach pose, turned by at most max_turn
  // (a larger offset needs a longer run-up).
  const double turn_limit = std::min(p.max_turn_rad, std::atan2(std::fabs(r.y), p.run_up_m));
  const double run_up = std::fabs(r.y) < p.min_step_m ? 0.0 : std::fabs(r.y) / std::tan(turn_limit);
  const double x_start = (xt - r.x >= run_up) ? r.x : xt - run_up;
  addTranslation(&plan, x_start - r.x, p, "reverse");
  if (std::fabs(r.y) < p.min_step_m) {
    addTranslation(&plan, xt - x_start, p, "drive forward");
    return plan;
  }
  const double turn = std::atan2(-r.y, xt - x_start);
  addRotation(&plan, turn, p, "rotate towards the rails");
  addTranslation(&plan, std::hypot(xt - x_start, r.y), p, "drive forward");
  addRotation(&plan, -turn, p, "rotate to align");
  return plan;
}

thorvald_base::Pose2D applyPlan(const thorvald_base::Pose2D& start, const std::vector<MotionStep>& plan) {
  thorvald_base::Pose2D pose = start;
  for (const MotionStep& s : plan) {
    if (s.kind == MotionStep::Kind::kRotate) {
      pose.yaw = thorvald_base::normalizeAngle(pose.yaw + s.amount);
    } else {
      pose.x += s.amount * std::cos(pose.yaw);
      pose.y += s.amount * std::sin(pose.yaw);
    }
  }
  return pose;
}

std::vector<double> railSearchRotations(double step_rad, double limit_rad) {
  std::vector<double> rotations;
  if (!(step_rad > 0.0) || !(limit_rad >= step_rad) || !std::isfinite(limit_rad)) return rotations;
  double heading = 0.0;
  for (int k = 1; k * step_rad <= limit_rad + 1e-9; ++k) {
    for (double sign : {1.0, -1.0}) {
      const double target = sign * k * step_rad;
      rotations.push_back(target - heading);
      heading = target;
    }
  }
  rotations.push_back(-heading);
  return rotations;
}

}  // namespace greenhouse_rail_nav
