#include "cotton_harvester/control/pure_pursuit.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace cotton_harvester {
namespace control {

namespace {
constexpr double kDegToRad = M_PI / 180.0;
}  // namespace

std::string PurePursuitParams::check() const {
  if (!(min_lookahead_m > 0.0)) return "min_lookahead_m: expected > 0";
  if (!(max_lookahead_m >= min_lookahead_m)) return "max_lookahead_m: expected >= min_lookahead_m";
  if (!(lookahead_m > 0.0)) return "lookahead_m: expected > 0";
  if (!(lookahead_per_mps >= 0.0)) return "lookahead_per_mps: expected >= 0";
  if (!(axle_to_joint_m > 0.0)) return "axle_to_joint_m: expected > 0";
  if (!(articulation_limit_deg > 0.0 && articulation_limit_deg < 90.0))
    return "articulation_limit_deg: expected in (0, 90)";
  if (!(goal_tolerance_m > 0.0)) return "goal_tolerance_m: expected > 0";
  if (!(search_window_m > 0.0)) return "search_window_m: expected > 0";
  if (!(heading_correction_gain >= 0.0) || !std::isfinite(heading_correction_gain))
    return "heading_correction_gain: expected >= 0";
  if (!(heading_correction_limit_deg >= 0.0 && heading_correction_limit_deg < 90.0))
    return "heading_correction_limit_deg: expected in [0, 90)";
  if (!(straight_path_deg > 0.0 && straight_path_deg < 90.0)) return "straight_path_deg: expected in (0, 90)";
  if (!(settled_articulation_deg > 0.0)) return "settled_articulation_deg: expected > 0";
  return "";
}

double articulationForCurvature(double curvature_1pm, double axle_to_joint_m) {
  return 2.0 * std::atan(axle_to_joint_m * curvature_1pm) / kDegToRad;
}

double curvatureForArticulation(double articulation_deg, double axle_to_joint_m) {
  return std::tan(0.5 * articulation_deg * kDegToRad) / axle_to_joint_m;
}

double minTurnRadius(double articulation_deg, double axle_to_joint_m) {
  return 1.0 / curvatureForArticulation(std::abs(articulation_deg), axle_to_joint_m);
}

PurePursuit::PurePursuit(const PurePursuitParams& params) : params_(params) {
  if (const std::string bad = params_.check(); !bad.empty()) throw std::invalid_argument("pure pursuit: " + bad);
}

void PurePursuit::setPath(const WaypointPath& path) {
  path_ = path;
  s_m_ = 0.0;
}

void PurePursuit::resetHeadingCorrection() {
  heading_correction_rad_ = 0.0;
  has_last_ = false;
  last_articulation_deg_ = 0.0;
}

double PurePursuit::lookahead(double speed_mps) const {
  const double l = params_.lookahead_m + params_.lookahead_per_mps * std::abs(speed_mps);
  return std::clamp(l, params_.min_lookahead_m, params_.max_lookahead_m);
}

PursuitStep PurePursuit::update(const Pose2& front_axle, double speed_mps) {
  PursuitStep step;
  if (path_.empty() || !std::isfinite(front_axle.x) || !std::isfinite(front_axle.y) || !std::isfinite(front_axle.yaw)) {
    step.finished = path_.empty();
    return step;
  }
  const Eigen::Vector2d p(front_axle.x, front_axle.y);
  const PathProjection proj = path_.project(p, s_m_, s_m_ + params_.search_window_m);
  s_m_ = std::max(s_m_, proj.s_m);
  step.lookahead_m = lookahead(std::isfinite(speed_mps) ? speed_mps : 0.0);
  step.s_m = s_m_;
  step.cross_track_m = proj.cross_track_m;
  // The heading correction integrates the cross-track over the distance driven along straight stretches only (a
  // curve's cross-track is the tracking's lag, not the heading's error).
  const double driven = has_last_ ? (p - last_).norm() : 0.0;
  last_ = p;
  has_last_ = true;
  const double bend = std::abs(wrapAngle(path_.headingAt(s_m_ + step.lookahead_m) - path_.headingAt(s_m_)));
  if (params_.heading_correction_gain > 0.0 && bend <= params_.straight_path_deg * kDegToRad && driven < 0.5 &&
      std::abs(last_articulation_deg_) <= params_.settled_articulation_deg) {
    const double limit = params_.heading_correction_limit_deg * kDegToRad;
    heading_correction_rad_ = std::clamp(
        heading_correction_rad_ + params_.heading_correction_gain * proj.cross_track_m * driven, -limit, limit);
  }
  step.heading_correction_rad = heading_correction_rad_;
  const double yaw = front_axle.yaw + heading_correction_rad_;
  step.heading_error_rad = wrapAngle(path_.headingAt(s_m_) - yaw);
  step.remaining_m = std::max(0.0, path_.lengthM() - s_m_);
  step.finished = step.remaining_m <= params_.goal_tolerance_m;
  // The goal: one lookahead along the path from the projection, in the rover's frame.
  const Eigen::Vector2d goal = path_.pointAt(s_m_ + step.lookahead_m) - p;
  const double c = std::cos(yaw), s = std::sin(yaw);
  const double gx = c * goal.x() + s * goal.y(), gy = -s * goal.x() + c * goal.y();
  const double d2 = gx * gx + gy * gy;
  step.curvature_1pm = d2 > 1e-9 ? 2.0 * gy / d2 : 0.0;
  const double angle = articulationForCurvature(step.curvature_1pm, params_.axle_to_joint_m);
  step.articulation_deg = std::clamp(angle, -params_.articulation_limit_deg, params_.articulation_limit_deg);
  last_articulation_deg_ = step.articulation_deg;
  return step;
}

}  // namespace control
}  // namespace cotton_harvester
