#include "greenhouse_rail_nav/rail_pair_selection.h"

#include <algorithm>
#include <cmath>

#include "greenhouse_rail_nav/pipe_axis.h"
#include "greenhouse_rail_nav/rail_set_layout.h"

namespace greenhouse_rail_nav {
namespace {

double lineAngle(const LineFit2D& a, const LineFit2D& b) { return angleBetweenLines(a.direction, b.direction); }

/// The partner of `rail` in the band's strip on one side (side: -1 right, +1 left), or std::nullopt.
std::optional<RailLine> partnerOnSide(const RailLine& rail, const RailBand& band, double side,
                                      const RailDetectorParams& p) {
  std::vector<int> strip;
  for (std::size_t k = 0; k < band.xy.size(); ++k) {
    if (std::abs(rail.fit.signedDistance(band.xy[k]) - side * p.rail_gauge_m) <= p.gauge_tolerance_m)
      strip.push_back(static_cast<int>(k));
  }
  if (static_cast<int>(strip.size()) < p.min_cluster_points) return std::nullopt;
  const RailLine first = makeRailLine(xyOf(band.points, strip));
  std::vector<int> close;  // second pass: only points near the fitted rail
  for (const int k : strip)
    if (std::abs(first.fit.signedDistance(band.xy[static_cast<std::size_t>(k)])) <= 0.5 * p.gauge_tolerance_m)
      close.push_back(k);
  if (static_cast<int>(close.size()) < p.min_cluster_points) return std::nullopt;
  const auto close_xy = xyOf(band.points, close);
  RailLine candidate = trimRailLine(close_xy, makeRailLine(close_xy), p.rail_trim_m);
  candidate.height_m = medianHeight(band.points, close);
  std::vector<Eigen::Vector2d> on_rail;
  for (const auto& q : close_xy)
    if (std::abs(candidate.fit.signedDistance(q)) <= 0.5 * p.rail_trim_m) on_rail.push_back(q);
  if (lineCoverage(on_rail, candidate.fit, 0.05) < p.min_partner_coverage) return std::nullopt;
  if (static_cast<int>(candidate.points) < p.min_cluster_points || candidate.fit.length() < p.min_line_length_m ||
      lineAngle(rail.fit, candidate.fit) > p.parallel_tolerance_rad ||
      std::abs(candidate.height_m - rail.height_m) > p.height_tolerance_m)
    return std::nullopt;
  return candidate;
}

}  // namespace

std::optional<std::size_t> partnerAmongLines(const std::vector<RailLine>& lines, std::size_t i,
                                             const RailDetectorParams& p) {
  std::optional<std::size_t> partner;
  double partner_error = p.gauge_tolerance_m;
  for (std::size_t j = 0; j < lines.size(); ++j) {
    if (j == i || lineAngle(lines[i].fit, lines[j].fit) > p.parallel_tolerance_rad ||
        std::abs(lines[j].height_m - lines[i].height_m) > p.height_tolerance_m)
      continue;
    const double error = std::abs(std::abs(lines[i].fit.signedDistance(lines[j].fit.centroid)) - p.rail_gauge_m);
    if (error <= partner_error) {
      partner_error = error;
      partner = j;
    }
  }
  return partner;
}

std::optional<RailLine> partnerFromBand(const RailLine& rail, const RailBand& band, const RailDetectorParams& p) {
  std::optional<RailLine> partner;
  for (const double side : {-1.0, 1.0}) {
    std::optional<RailLine> candidate = partnerOnSide(rail, band, side, p);
    if (candidate && (!partner || candidate->points > partner->points)) partner = std::move(candidate);
  }
  return partner;
}

std::array<double, 3> railPairVariance(const RailPair& pair, const thorvald_base::Pose2D& base_in_rail,
                                       const RailDetectorParams& p) {
  double var_yaw_fit = 0.0, var_offset_fit = 0.0;
  for (const RailLine* r : {&pair.first, &pair.second}) {
    const double n = std::max<double>(2.0, static_cast<double>(r->points));
    const double len = std::max(r->fit.length(), 1e-3);
    var_yaw_fit += r->fit.rms_residual * r->fit.rms_residual / (n * len * len / 12.0) / 4.0;
    var_offset_fit += r->fit.rms_residual * r->fit.rms_residual / n / 4.0;
  }
  const double lever = std::abs(base_in_rail.x);
  return {p.sigma_x_m * p.sigma_x_m + p.voxel_size_m * p.voxel_size_m,
          p.sigma_y_m * p.sigma_y_m + var_offset_fit + lever * lever * var_yaw_fit,
          p.sigma_yaw_rad * p.sigma_yaw_rad + var_yaw_fit};
}

std::optional<RailPairChoice> selectRailPair(const std::vector<RailLine>& lines, const RailBand& band,
                                             bool search_band_for_partner, const Eigen::Vector3d& camera_xyz,
                                             const RailDetectorParams& p, std::string* why) {
  std::string reason = "no rail at " + formatMetres(p.rail_gauge_m, 3) + " +- " + formatMetres(p.gauge_tolerance_m, 3) +
                       " m beside any of " + std::to_string(lines.size()) + " straight lines";
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const RailLine& best = lines[i];
    std::optional<RailLine> partner;
    if (const auto j = partnerAmongLines(lines, i, p)) {
      partner = lines[*j];
    } else if (search_band_for_partner) {
      partner = partnerFromBand(best, band, p);
    }
    if (!partner) continue;
    RailPairChoice choice;
    choice.pair = makeRailPair(pipeAxisLine(best, camera_xyz, band.raw, p.pipe_radius_m),
                               pipeAxisLine(*partner, camera_xyz, band.raw, p.pipe_radius_m));
    const thorvald_base::Pose2D base_in_rail = choice.pair.rail_in_base.inverse();
    if (std::abs(base_in_rail.y) > p.max_lateral_offset_m) {
      reason = "rail pair found " + formatMetres(base_in_rail.y, 3) + " m to the side (limit " +
               formatMetres(p.max_lateral_offset_m, 3) + " m): a neighbouring rail set";
      continue;
    }
    choice.fit_score = best.fit.linearity;
    choice.variance = railPairVariance(choice.pair, base_in_rail, p);
    return choice;
  }
  if (why) *why = reason;
  return std::nullopt;
}

}  // namespace greenhouse_rail_nav
