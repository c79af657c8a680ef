#include "thorvald_navigation/scan_matcher.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/LU>

namespace thorvald_navigation {

std::string ScanMatcherParams::validate() const {
  if (!(sigma_hit_m > 0.0)) return "sigma_hit_m must be > 0";
  if (!(coarse_sigma_m >= 0.0)) return "coarse_sigma_m must be >= 0";
  if (!(inlier_m > 0.0)) return "inlier_m must be > 0";
  if (max_iterations < 1 || max_iterations > 1000) return "max_iterations must be in [1, 1000]";
  if (!(prior_sigma_xy_m >= 0.0) || !(prior_sigma_yaw_rad >= 0.0)) return "prior sigmas must be >= 0";
  return {};
}

std::string GlobalSearchParams::validate() const {
  if (!(step_xy_m > 0.0)) return "global step_xy_m must be > 0";
  if (!(step_yaw_rad > 0.0) || step_yaw_rad > thorvald_base::kPi) return "global step_yaw_rad must be in (0, pi]";
  if (max_points < 3) return "global max_points must be >= 3";
  if (refine_best < 1) return "global refine_best must be >= 1";
  if (!(min_clearance_m >= 0.0)) return "global min_clearance_m must be >= 0";
  if (!(window_xy_m >= 0.0) || !(window_yaw_rad > 0.0)) return "search window must be >= 0 m and > 0 rad";
  return {};
}

std::vector<Eigen::Vector2d> subsample(const std::vector<Eigen::Vector2d>& points, int max_points) {
  if (max_points <= 0 || static_cast<int>(points.size()) <= max_points) return points;
  std::vector<Eigen::Vector2d> out;
  out.reserve(static_cast<std::size_t>(max_points));
  const double step = static_cast<double>(points.size()) / max_points;
  for (int i = 0; i < max_points; ++i) out.push_back(points[static_cast<std::size_t>(i * step)]);
  return out;
}

namespace {

void evaluate(const DistanceField& field, const std::vector<Eigen::Vector2d>& pts, const thorvald_base::Pose2D& pose,
              double inlier_m, MatchResult* r) {
  int inliers = 0;
  double sum_sq = 0.0;
  for (const auto& p : pts) {
    const double d = field.distance(pose.transformPoint(p));
    if (d < inlier_m) {
      ++inliers;
      sum_sq += d * d;
    }
  }
  r->points = static_cast<int>(pts.size());
  r->inlier_fraction = pts.empty() ? 0.0 : static_cast<double>(inliers) / pts.size();
  r->rms_m = inliers > 0 ? std::sqrt(sum_sq / inliers) : 0.0;
}

/// The robust (Cauchy) cost of a pose: the beams' distances to the nearest wall plus a Gaussian prior centred on the
/// initial pose; with `hess` and `grad` also its Gauss-Newton Hessian and gradient (IRLS weights).
class RobustCost {
 public:
  RobustCost(const DistanceField& field, const std::vector<Eigen::Vector2d>& points_base,
             const thorvald_base::Pose2D& initial, const ScanMatcherParams& params)
      : field_(field), points_(points_base), initial_(initial), s2_(params.sigma_hit_m * params.sigma_hit_m) {
    wxy_ = params.prior_sigma_xy_m > 0.0 ? 1.0 / (params.prior_sigma_xy_m * params.prior_sigma_xy_m) : 0.0;
    wyaw_ = params.prior_sigma_yaw_rad > 0.0 ? 1.0 / (params.prior_sigma_yaw_rad * params.prior_sigma_yaw_rad) : 0.0;
  }

  double operator()(const thorvald_base::Pose2D& q, Eigen::Matrix3d* hess, Eigen::Vector3d* grad) const {
    double c = 0.0;
    if (hess) hess->setZero();
    if (grad) grad->setZero();
    const double cs = std::cos(q.yaw), sn = std::sin(q.yaw);
    for (const auto& p : points_) {
      const Eigen::Vector2d w(q.x + cs * p.x() - sn * p.y(), q.y + sn * p.x() + cs * p.y());
      Eigen::Vector2d g;
      const double d = field_.distance(w, hess ? &g : nullptr);
      if (d >= field_.maxDistance() * 0.999) {  // no wall in reach: says nothing about the pose
        c += std::log1p(field_.maxDistance() * field_.maxDistance() / s2_);
        continue;
      }
      c += std::log1p(d * d / s2_);
      if (hess) {
        const double wt = 1.0 / (1.0 + d * d / s2_);  // Cauchy IRLS weight
        const Eigen::Vector3d j(g.x(), g.y(), g.x() * (-sn * p.x() - cs * p.y()) + g.y() * (cs * p.x() - sn * p.y()));
        *hess += wt * j * j.transpose() / s2_;
        *grad += wt * j * d / s2_;
      }
    }
    return c + prior(q, hess, grad);
  }

 private:
  double prior(const thorvald_base::Pose2D& q, Eigen::Matrix3d* hess, Eigen::Vector3d* grad) const {
    const double dx = q.x - initial_.x, dy = q.y - initial_.y;
    const double dyaw = thorvald_base::normalizeAngle(q.yaw - initial_.yaw);
    if (hess) {
      (*hess)(0, 0) += wxy_;
      (*hess)(1, 1) += wxy_;
      (*hess)(2, 2) += wyaw_;
      (*grad)(0) += wxy_ * dx;
      (*grad)(1) += wxy_ * dy;
      (*grad)(2) += wyaw_ * dyaw;
    }
    return wxy_ * (dx * dx + dy * dy) + wyaw_ * dyaw * dyaw;
  }

  const DistanceField& field_;
  const std::vector<Eigen::Vector2d>& points_;
  thorvald_base::Pose2D initial_;
  double s2_, wxy_, wyaw_;
};

/// Levenberg-Marquardt descent of `cost` from `*pose`; leaves the optimum in `*pose` and its Hessian in `*h`.
/// Returns the iterations done.
int minimise(const RobustCost& cost, int max_iterations, thorvald_base::Pose2D* pose, Eigen::Matrix3d* h) {
  double lambda = 1e-3;
  Eigen::Vector3d g;
  double c = cost(*pose, h, &g);
  int it = 0;
  for (; it < max_iterations; ++it) {
    Eigen::Matrix3d a = *h;
    a.diagonal() += lambda * (h->diagonal().array() + 1e-9).matrix();
    const Eigen::Vector3d step = -a.ldlt().solve(g);
    if (!step.allFinite()) break;
    const thorvald_base::Pose2D trial{pose->x + step(0), pose->y + step(1),
                                      thorvald_base::normalizeAngle(pose->yaw + step(2))};
    Eigen::Matrix3d h2;
    Eigen::Vector3d g2;
    const double c2 = cost(trial, &h2, &g2);
    if (c2 < c) {
      *pose = trial;
      c = c2;
      *h = h2;
      g = g2;
      lambda = std::max(1e-6, lambda * 0.3);
      if (step.head<2>().norm() < 1e-5 && std::abs(step(2)) < 1e-5) break;
    } else {
      lambda *= 10.0;
      if (lambda > 1e6) break;
    }
  }
  return it;
}

}  // namespace

MatchResult matchScan(const DistanceField& field, const std::vector<Eigen::Vector2d>& points_base,
                      const thorvald_base::Pose2D& initial, const ScanMatcherParams& params) {
  MatchResult result;
  result.pose = initial;
  if (field.empty() || points_base.empty() || !initial.finite()) {
    result.covariance *= 1e6;
    return result;
  }
  thorvald_base::Pose2D pose = initial;  // the prior stays centred on `initial`
  if (params.coarse_sigma_m > params.sigma_hit_m) {
    ScanMatcherParams coarse = params;
    coarse.sigma_hit_m = params.coarse_sigma_m;
    coarse.coarse_sigma_m = 0.0;
    coarse.max_iterations = std::max(5, params.max_iterations / 2);
    pose = matchScan(field, points_base, initial, coarse).pose;
  }
  Eigen::Matrix3d h = Eigen::Matrix3d::Identity();
  result.iterations = minimise(RobustCost(field, points_base, initial, params), params.max_iterations, &pose, &h);
  result.pose = pose;
  evaluate(field, points_base, pose, params.inlier_m, &result);
  // Laplace approximation of the robust cost around the optimum; the Cauchy weights make it an information
  // matrix that shrinks when few beams agree.
  Eigen::Matrix3d info = h;
  info.diagonal().array() += 1e-6;
  const Eigen::Matrix3d cov = info.inverse();
  result.covariance = cov.allFinite() ? cov : Eigen::Matrix3d::Identity() * 1e6;
  return result;
}

namespace {

struct Candidate {
  double score;
  thorvald_base::Pose2D pose;
};

/// The cells and headings a global search scores: every stride-th cell of the map (or of the window around the
/// centre), headings evenly over the full turn (or the yaw window) with their cosines and sines.
struct SearchGrid {
  int stride = 1, x_lo = 0, y_lo = 0, x_hi = 0, y_hi = 0, headings = 1, last_heading = 0;
  double yaw0 = 0.0, yaw_step = 0.0;
  std::vector<double> cs, sn;
};

SearchGrid searchGrid(const thorvald_map::OccupancyGrid& free_space, const GlobalSearchParams& gparams) {
  SearchGrid grid;
  grid.stride = std::max(1, static_cast<int>(std::lround(gparams.step_xy_m / free_space.resolution_m)));
  const bool windowed = gparams.window_xy_m > 0.0;
  const double yaw_span = windowed ? std::min(thorvald_base::kPi, gparams.window_yaw_rad) : thorvald_base::kPi;
  grid.yaw0 = windowed ? gparams.center.yaw - yaw_span : -thorvald_base::kPi;
  grid.headings = std::max(1, static_cast<int>(std::ceil(2.0 * yaw_span / gparams.step_yaw_rad)));
  grid.yaw_step = 2.0 * yaw_span / grid.headings;
  grid.cs.resize(grid.headings + 1);
  grid.sn.resize(grid.headings + 1);
  for (int k = 0; k <= grid.headings; ++k) {
    grid.cs[k] = std::cos(grid.yaw0 + k * grid.yaw_step);
    grid.sn[k] = std::sin(grid.yaw0 + k * grid.yaw_step);
  }
  grid.x_hi = free_space.width - 1;
  grid.y_hi = free_space.height - 1;
  if (windowed) {
    const Eigen::Vector2i lo =
        free_space.cellOf({gparams.center.x - gparams.window_xy_m, gparams.center.y - gparams.window_xy_m});
    const Eigen::Vector2i hi =
        free_space.cellOf({gparams.center.x + gparams.window_xy_m, gparams.center.y + gparams.window_xy_m});
    grid.x_lo = std::max(0, lo.x());
    grid.y_lo = std::max(0, lo.y());
    grid.x_hi = std::min(grid.x_hi, hi.x());
    grid.y_hi = std::min(grid.y_hi, hi.y());
  }
  grid.last_heading = (windowed && yaw_span < thorvald_base::kPi) ? grid.headings : grid.headings - 1;
  return grid;
}

/// Scores every pose of the grid on free cells with enough clearance: the sum of the beams' Cauchy weights.
std::vector<Candidate> scoreCandidates(const DistanceField& field, const thorvald_map::OccupancyGrid& free_space,
                                       const std::vector<Eigen::Vector2d>& pts, const GlobalSearchParams& gparams,
                                       const ScanMatcherParams& params) {
  const SearchGrid grid = searchGrid(free_space, gparams);
  const double inv_s2 = 1.0 / std::pow(std::max(params.sigma_hit_m, 0.5 * gparams.step_xy_m), 2);
  std::vector<Candidate> all;
  for (int cy = grid.y_lo + grid.stride / 2; cy <= grid.y_hi; cy += grid.stride) {
    for (int cx = grid.x_lo + grid.stride / 2; cx <= grid.x_hi; cx += grid.stride) {
      const int v = free_space.at(cx, cy);
      if (v < 0 || v > 19) continue;
      const Eigen::Vector2d c = free_space.cellCentre(cx, cy);
      if (field.distance(c) < gparams.min_clearance_m) continue;
      for (int k = 0; k <= grid.last_heading; ++k) {
        const double cs = grid.cs[k], sn = grid.sn[k];
        double score = 0.0;
        for (const auto& p : pts) {
          const double d = field.distance({c.x() + cs * p.x() - sn * p.y(), c.y() + sn * p.x() + cs * p.y()});
          score += 1.0 / (1.0 + d * d * inv_s2);
        }
        all.push_back({score, {c.x(), c.y(), thorvald_base::normalizeAngle(grid.yaw0 + k * grid.yaw_step)}});
      }
    }
  }
  return all;
}

/// Refines the best `keep` candidates (sorted first) with the scan matcher, skipping near-duplicates of one already
/// refined, up to refine_best of them; sorted by inlier fraction, best first.
std::vector<MatchResult> refineBest(const DistanceField& field, const std::vector<Eigen::Vector2d>& points_base,
                                    const std::vector<Candidate>& all, std::size_t keep,
                                    const GlobalSearchParams& gparams, const ScanMatcherParams& params) {
  std::vector<MatchResult> refined;
  ScanMatcherParams loose = params;
  loose.prior_sigma_xy_m = loose.prior_sigma_yaw_rad = 0.0;
  loose.sigma_hit_m = std::max(params.sigma_hit_m, 0.1);
  loose.coarse_sigma_m = 0.0;
  const auto refine_pts = subsample(points_base, 4 * gparams.max_points);
  for (std::size_t i = 0; i < keep && static_cast<int>(refined.size()) < gparams.refine_best; ++i) {
    bool duplicate = false;
    for (const auto& r : refined)
      duplicate =
          duplicate || (std::hypot(r.pose.x - all[i].pose.x, r.pose.y - all[i].pose.y) < gparams.step_xy_m &&
                        std::abs(thorvald_base::normalizeAngle(r.pose.yaw - all[i].pose.yaw)) < gparams.step_yaw_rad);
    if (duplicate) continue;
    MatchResult coarse = matchScan(field, refine_pts, all[i].pose, loose);
    MatchResult fine = matchScan(field, refine_pts, coarse.pose, params);
    refined.push_back(fine);
  }
  std::sort(refined.begin(), refined.end(),
            [](const MatchResult& a, const MatchResult& b) { return a.inlier_fraction > b.inlier_fraction; });
  return refined;
}

}  // namespace

GlobalResult globalSearch(const DistanceField& field, const thorvald_map::OccupancyGrid& free_space,
                          const std::vector<Eigen::Vector2d>& points_base, const GlobalSearchParams& gparams,
                          const ScanMatcherParams& params) {
  GlobalResult out;
  const auto pts = subsample(points_base, gparams.max_points);
  if (field.empty() || pts.size() < 3 || !free_space.check().empty()) return out;
  std::vector<Candidate> all = scoreCandidates(field, free_space, pts, gparams, params);
  out.candidates = static_cast<int>(all.size());
  if (all.empty()) return out;
  const std::size_t keep = std::min(all.size(), static_cast<std::size_t>(gparams.refine_best) * 4);
  std::partial_sort(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(keep), all.end(),
                    [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
  const std::vector<MatchResult> refined = refineBest(field, points_base, all, keep, gparams, params);
  out.found = true;
  out.best = refined.front();
  // The runner-up is the best refined pose clearly elsewhere: a match almost as good makes the result ambiguous.
  for (std::size_t i = 1; i < refined.size(); ++i) {
    const auto& r = refined[i];
    const double dist = std::hypot(r.pose.x - out.best.pose.x, r.pose.y - out.best.pose.y);
    if (dist > 0.5 || std::abs(thorvald_base::normalizeAngle(r.pose.yaw - out.best.pose.yaw)) > 0.3) {
      out.runner_up = r;
      break;
    }
  }
  out.ambiguous = out.runner_up.inlier_fraction > 0.95 * out.best.inlier_fraction;
  return out;
}

}  // namespace thorvald_navigation
