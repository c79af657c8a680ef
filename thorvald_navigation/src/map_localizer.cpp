#include "thorvald_navigation/map_localizer.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace thorvald_navigation {

std::string LocalizerParams::validate() const {
  if (max_beams < 10 || max_beams > 5000) return "max_beams must be in [10, 5000]";
  if (!(field_max_distance_m > 0.0)) return "likelihood max distance must be > 0";
  if (!(odom_sigma_xy_m > 0.0) || !(odom_sigma_yaw_rad > 0.0)) return "odometry sigmas must be > 0";
  if (!(odom_sigma_per_m >= 0.0) || !(odom_sigma_yaw_per_rad >= 0.0)) return "odometry sigma rates must be >= 0";
  if (!(lost_inlier_fraction >= 0.0 && lost_inlier_fraction <= uncertain_inlier_fraction &&
        uncertain_inlier_fraction <= 1.0))
    return "need 0 <= lost_inlier_fraction <= uncertain_inlier_fraction <= 1";
  if (lost_after_scans < 1 || confirm_scans < 0) return "lost_after_scans must be >= 1, confirm_scans >= 0";
  if (!(max_jump_m > 0.0)) return "max_jump must be > 0";
  if (!(recheck_xy_m >= 0.0) || !(recheck_yaw_rad > 0.0 && recheck_yaw_rad <= thorvald_base::kPi))
    return "recheck_xy must be >= 0 m and recheck_yaw in (0, pi] rad";
  if (recheck_every_scans < 1) return "recheck_every_scans must be >= 1";
  if (!(recheck_inlier_fraction >= 0.0 && recheck_inlier_fraction <= 1.0))
    return "recheck_inlier_fraction must be in [0, 1]";
  const std::string m = matcher.validate();
  return m.empty() ? global.validate() : m;
}

const char* statusName(LocalizationStatus s) {
  switch (s) {
    case LocalizationStatus::kNoPose:
      return "no pose";
    case LocalizationStatus::kLocalized:
      return "localized";
    case LocalizationStatus::kUncertain:
      return "uncertain";
    case LocalizationStatus::kLost:
      return "lost";
  }
  return "?";
}

std::string MapLocalizer::setMap(const thorvald_map::OccupancyGrid& map, const thorvald_map::WallSurface* surface) {
  const std::string problem = map.check();
  if (!problem.empty()) return problem;
  if (surface) {
    const std::string bad = surface->check(map.data.size());
    if (!bad.empty()) return bad;
  }
  DistanceField field(map, params_.field_max_distance_m, 65, true, surface);
  if (field.occupiedCells() < 10) return "map has fewer than 10 occupied cells: nothing to localise against";
  map_ = map;
  field_ = std::move(field);
  return {};
}

void MapLocalizer::setPose(const thorvald_base::Pose2D& map_pose, const thorvald_base::Pose2D& odom) {
  map_to_odom_ = map_pose * odom.inverse();
  last_odom_ = odom;
  have_last_odom_ = true;
  bad_scans_ = 0;
  weak_scans_ = 0;
  confirm_left_ = 0;
  global_requested_ = false;
  window_xy_m_ = 0.0;
  status_ = LocalizationStatus::kLocalized;
}

LocalizationUpdate MapLocalizer::update(const thorvald_base::Pose2D& odom,
                                        const std::vector<Eigen::Vector2d>& points_base) {
  LocalizationUpdate u;
  u.status = status_;
  u.pose = map_to_odom_ * odom;
  if (field_.empty()) {
    u.message = "no map";
    return u;
  }
  if (!odom.finite()) {
    u.message = "odometry pose is not finite";
    return u;
  }
  const auto pts = subsample(points_base, params_.max_beams);
  if (pts.size() < 10) {
    u.message = "fewer than 10 valid beams";
    return u;
  }
  if (global_requested_) {
    globalUpdate(odom, points_base, &u);
    return u;
  }
  if (status_ == LocalizationStatus::kNoPose) {
    u.message = "no initial pose: set one (initialpose) or call global_localization";
    return u;
  }
  if (status_ == LocalizationStatus::kLost && params_.recheck_xy_m > 0.0 && --scans_to_recheck_ <= 0) {
    scans_to_recheck_ = params_.recheck_every_scans;
    if (recheck(odom, points_base, &u)) return u;
  }
  const thorvald_base::Pose2D predicted = map_to_odom_ * odom;
  const MatchResult m = matchScan(field_, pts, predicted, trackingParams(odom));
  last_odom_ = odom;
  have_last_odom_ = true;
  u.inlier_fraction = m.inlier_fraction;
  if (rejectMatch(m, predicted, &u)) return u;
  acceptMatch(m, odom, &u);
  return u;
}

void MapLocalizer::globalUpdate(const thorvald_base::Pose2D& odom, const std::vector<Eigen::Vector2d>& points_base,
                                LocalizationUpdate* u) {
  GlobalSearchParams gp = params_.global;
  if (window_xy_m_ > 0.0) {  // a local search: finer steps over the small window
    gp.window_xy_m = window_xy_m_;
    gp.window_yaw_rad = window_yaw_rad_;
    gp.center = window_center_;
    gp.step_xy_m = std::min(gp.step_xy_m, 0.1);
    gp.step_yaw_rad = std::min(gp.step_yaw_rad, 0.05);
    gp.min_clearance_m = 0.0;
  }
  const GlobalResult g = globalSearch(field_, map_, points_base, gp, params_.matcher);
  global_requested_ = false;
  if (!g.found) {
    status_ = LocalizationStatus::kLost;
    u->status = status_;
    u->message = "global localisation found no candidate pose";
    return;
  }
  adopt(g, odom, "global localisation", u);
}

ScanMatcherParams MapLocalizer::trackingParams(const thorvald_base::Pose2D& odom) const {
  const thorvald_base::Pose2D delta = have_last_odom_ ? last_odom_.inverse() * odom : thorvald_base::Pose2D{};
  const double moved = std::hypot(delta.x, delta.y), turned = std::abs(delta.yaw);
  ScanMatcherParams mp = params_.matcher;
  mp.prior_sigma_xy_m = params_.odom_sigma_xy_m + params_.odom_sigma_per_m * moved;
  mp.prior_sigma_yaw_rad = params_.odom_sigma_yaw_rad + params_.odom_sigma_yaw_per_rad * turned;
  if (status_ == LocalizationStatus::kLost) {  // odometry has drifted for a while: let the scan pull harder
    mp.prior_sigma_xy_m *= 5.0;
    mp.prior_sigma_yaw_rad *= 5.0;
  }
  return mp;
}

bool MapLocalizer::rejectMatch(const MatchResult& m, const thorvald_base::Pose2D& predicted, LocalizationUpdate* u) {
  const double jump = std::hypot(m.pose.x - predicted.x, m.pose.y - predicted.y);
  if (m.inlier_fraction < params_.lost_inlier_fraction || jump > params_.max_jump_m || !m.pose.finite()) {
    ++bad_scans_;
    // A match that fits the map well but lies farther than max_jump from the odometry: the pose is known wrong.
    const bool known_wrong =
        m.pose.finite() && jump > params_.max_jump_m && m.inlier_fraction >= params_.uncertain_inlier_fraction;
    std::ostringstream msg;
    msg << "scan not used: " << m.inlier_fraction << " of beams matched, correction " << jump << " m"
        << (known_wrong ? " (more than max_jump: odometry and map disagree)" : "");
    u->message = msg.str();
    if ((known_wrong || bad_scans_ >= params_.lost_after_scans) && status_ != LocalizationStatus::kLost) {
      status_ = LocalizationStatus::kLost;
      scans_to_recheck_ = 1;  // re-check on the next scan
    }
    u->status = status_;
    u->pose = predicted;
    return true;
  }
  bad_scans_ = 0;
  // Weak matches are used for a moment (a passer-by hiding walls), not for long: a run of them, or any while lost,
  // means the pose is doubtful, and the odometry prediction alone is kept while the re-check looks for the robot.
  const bool weak = m.inlier_fraction < params_.uncertain_inlier_fraction;
  weak_scans_ = weak ? weak_scans_ + 1 : 0;
  if (weak && (status_ == LocalizationStatus::kLost || weak_scans_ >= params_.lost_after_scans)) {
    if (status_ != LocalizationStatus::kLost) scans_to_recheck_ = 1;
    status_ = LocalizationStatus::kLost;
    std::ostringstream msg;
    msg << "scan not used: only " << m.inlier_fraction << " of beams matched for " << weak_scans_ << " scans";
    u->message = msg.str();
    u->status = status_;
    u->pose = predicted;
    return true;
  }
  return false;
}

void MapLocalizer::acceptMatch(const MatchResult& m, const thorvald_base::Pose2D& odom, LocalizationUpdate* u) {
  map_to_odom_ = m.pose * odom.inverse();
  if (status_ == LocalizationStatus::kLost) confirm_left_ = params_.confirm_scans;  // found again by tracking
  if (m.inlier_fraction < params_.uncertain_inlier_fraction) {
    status_ = LocalizationStatus::kUncertain;
  } else if (confirm_left_ > 0) {
    --confirm_left_;
    status_ = confirm_left_ == 0 ? LocalizationStatus::kLocalized : LocalizationStatus::kUncertain;
  } else {
    status_ = LocalizationStatus::kLocalized;
  }
  u->used = true;
  u->pose = m.pose;
  u->covariance = m.covariance;
  u->status = status_;
}

void MapLocalizer::adopt(const GlobalResult& g, const thorvald_base::Pose2D& odom, const std::string& what,
                         LocalizationUpdate* u) {
  setPose(g.best.pose, odom);
  confirm_left_ = params_.confirm_scans;
  status_ = (g.ambiguous || g.best.inlier_fraction < params_.uncertain_inlier_fraction || confirm_left_ > 0)
                ? LocalizationStatus::kUncertain
                : LocalizationStatus::kLocalized;
  std::ostringstream msg;
  msg << what << ": " << g.candidates << " poses scored, best (" << g.best.pose.x << ", " << g.best.pose.y << ", "
      << g.best.pose.yaw << ") with " << g.best.inlier_fraction << " of beams matched"
      << (g.ambiguous ? ", ambiguous" : "");
  u->message = msg.str();
  u->used = true;
  u->pose = g.best.pose;
  u->covariance = g.best.covariance;
  u->inlier_fraction = g.best.inlier_fraction;
  u->status = status_;
}

bool MapLocalizer::recheck(const thorvald_base::Pose2D& odom, const std::vector<Eigen::Vector2d>& points_base,
                           LocalizationUpdate* u) {
  GlobalSearchParams gp = params_.global;
  gp.window_xy_m = params_.recheck_xy_m;
  gp.window_yaw_rad = params_.recheck_yaw_rad;
  gp.center = map_to_odom_ * odom;
  gp.step_xy_m = std::min(gp.step_xy_m, 0.1);
  gp.step_yaw_rad = std::min(gp.step_yaw_rad, 0.05);
  gp.min_clearance_m = 0.0;
  const GlobalResult g = globalSearch(field_, map_, points_base, gp, params_.matcher);
  if (g.found && !g.ambiguous && g.best.inlier_fraction >= params_.recheck_inlier_fraction) {
    adopt(g, odom, "relocalised by the re-check around odometry", u);
    return true;
  }
  std::ostringstream msg;
  msg << "lost; the re-check within " << params_.recheck_xy_m << " m found "
      << (!g.found ? "no candidate" : (g.ambiguous ? "two poses matching alike" : "no pose matching well enough"))
      << (g.found ? " (best " + std::to_string(g.best.inlier_fraction) + " of beams)" : std::string());
  u->message = msg.str();
  return false;
}

}  // namespace thorvald_navigation
