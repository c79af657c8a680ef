#include "greenhouse_rail_nav/rail_line_candidates.h"

#include <algorithm>
#include <cmath>

#include "greenhouse_rail_nav/rail_band.h"

namespace greenhouse_rail_nav {

std::optional<RailLine> railLineFromCluster(const std::vector<Eigen::Vector3f>& band, const std::vector<int>& cluster,
                                            const RailDetectorParams& p) {
  const auto xy = xyOf(band, cluster);
  const RailLine raw = makeRailLine(xy);
  const double heading = std::atan2(raw.fit.direction.y(), raw.fit.direction.x());
  if (!(raw.fit.length() >= p.min_line_length_m && raw.fit.linearity >= p.min_linearity &&
        std::abs(heading) <= p.max_abs_yaw_rad))
    return std::nullopt;
  RailLine rail = trimRailLine(xy, raw, p.rail_trim_m);
  rail.height_m = medianHeight(band, cluster);
  return rail;
}

std::optional<RailLine> railLineFromRansac(const std::vector<Eigen::Vector3f>& band, const RansacLine& line,
                                           const RailDetectorParams& p) {
  // Keep RANSAC's own model: its direction, positioned at the inliers' mean, extents from the inliers.
  const auto xy = xyOf(band, line.inliers);
  RailLine rail = makeRailLine(xy);
  const Eigen::Vector2d d = Eigen::Vector2d(line.direction.x(), line.direction.y());
  if (d.norm() < 0.5) return std::nullopt;  // a vertical line is no rail
  rail.fit.direction = d.x() < 0.0 ? Eigen::Vector2d(-d.normalized()) : Eigen::Vector2d(d.normalized());
  const Eigen::Vector2d model_point(line.point.x(), line.point.y());
  rail.fit.centroid = model_point + rail.fit.direction * rail.fit.direction.dot(rail.fit.centroid - model_point);
  std::vector<double> along;
  for (const auto& q : xy) along.push_back(rail.fit.along(q));
  std::sort(along.begin(), along.end());
  rail.near_end = along[static_cast<std::size_t>(0.02 * along.size())];
  rail.fit.s_min = along.front();
  rail.fit.s_max = along.back();
  const double heading = std::atan2(rail.fit.direction.y(), rail.fit.direction.x());
  rail.height_m = medianHeight(band, line.inliers);
  if (!(rail.fit.length() >= p.min_line_length_m && std::abs(heading) <= p.max_abs_yaw_rad)) return std::nullopt;
  return rail;
}

RailLineCandidates clusterRailLines(const std::vector<Eigen::Vector3f>& band, const RailDetectorParams& p) {
  RailLineCandidates out;
  const auto clusters = euclideanClusters(band, p.cluster_tolerance_m, p.min_cluster_points, p.max_cluster_points);
  out.groups = clusters.size();
  for (const auto& cluster : clusters)
    if (auto rail = railLineFromCluster(band, cluster, p)) out.lines.push_back(std::move(*rail));
  std::sort(out.lines.begin(), out.lines.end(),
            [](const RailLine& a, const RailLine& b) { return a.fit.linearity > b.fit.linearity; });
  return out;
}

RailLineCandidates ransacRailLines(const std::vector<Eigen::Vector3f>& band, const RailDetectorParams& p) {
  RailLineCandidates out;
  const auto found =
      ransacLines(band, p.ransac_distance_m, p.ransac_max_lines, p.min_cluster_points, p.ransac_iterations);
  out.groups = found.size();
  for (const auto& line : found)
    if (auto rail = railLineFromRansac(band, line, p)) out.lines.push_back(std::move(*rail));
  std::sort(out.lines.begin(), out.lines.end(),
            [](const RailLine& a, const RailLine& b) { return a.points > b.points; });
  return out;
}

}  // namespace greenhouse_rail_nav
