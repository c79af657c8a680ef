#include "greenhouse_rail_nav/line_extraction.h"

#include <algorithm>
#include <cmath>
#include <random>

namespace greenhouse_rail_nav {
namespace {

bool acceptable(const LineFit2D& fit, const LineExtractionParams& params) {
  // Linearity alone lets a long wall with a short wall joined at the corner pass as one line; the RMS
  // distance of the cells to the line does not.
  return fit.linearity >= params.min_linearity && fit.length() >= params.min_length_m &&
         fit.rms_residual <= params.split_inlier_m;
}

/// Splits points near one line into runs without gaps longer than max_gap (sorted along the line).
std::vector<std::vector<Eigen::Vector2d>> contiguousRuns(std::vector<Eigen::Vector2d> points, const LineFit2D& line,
                                                         double max_gap) {
  std::sort(points.begin(), points.end(),
            [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return line.along(a) < line.along(b); });
  std::vector<std::vector<Eigen::Vector2d>> runs;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (i == 0 || line.along(points[i]) - line.along(points[i - 1]) > max_gap) runs.emplace_back();
    runs.back().push_back(points[i]);
  }
  return runs;
}

/// Sequential RANSAC inside one cluster.
void splitCluster(std::vector<Eigen::Vector2d> remaining, const LineExtractionParams& params,
                  std::vector<LineSegment>* out) {
  std::mt19937 rng(12345);
  const std::size_t min_points = 5;
  for (int line = 0; line < params.max_lines_per_cluster && remaining.size() >= min_points; ++line) {
    std::uniform_int_distribution<std::size_t> pick(0, remaining.size() - 1);
    std::size_t best_count = 0;
    LineFit2D best;
    for (int iter = 0; iter < 200; ++iter) {
      const Eigen::Vector2d a = remaining[pick(rng)], b = remaining[pick(rng)];
      if ((b - a).norm() < params.min_length_m * 0.25) continue;
      LineFit2D candidate;
      candidate.centroid = a;
      candidate.direction = (b - a).normalized();
      std::size_t count = 0;
      for (const auto& p : remaining) count += std::abs(candidate.signedDistance(p)) <= params.split_inlier_m;
      if (count > best_count) {
        best_count = count;
        best = candidate;
      }
    }
    if (best_count < min_points) break;
    std::vector<Eigen::Vector2d> inliers, outliers;
    for (const auto& p : remaining) {
      (std::abs(best.signedDistance(p)) <= params.split_inlier_m ? inliers : outliers).push_back(p);
    }
    bool took_any = false;
    for (auto& run : contiguousRuns(inliers, best, params.max_gap_m)) {
      LineSegment segment{fitLine(run), std::move(run)};
      if (acceptable(segment.fit, params)) {
        out->push_back(std::move(segment));
        took_any = true;
      } else {
        outliers.insert(outliers.end(), segment.points.begin(), segment.points.end());
      }
    }
    if (!took_any) break;
    remaining = std::move(outliers);
  }
}

bool collinear(const LineFit2D& a, const LineFit2D& b, const LineExtractionParams& params) {
  const double angle = std::acos(std::min(1.0, std::abs(a.direction.dot(b.direction))));
  return angle <= params.merge_angle_rad && std::abs(a.signedDistance(b.centroid)) <= params.merge_offset_m &&
         std::abs(b.signedDistance(a.centroid)) <= params.merge_offset_m;
}

}  // namespace

std::vector<LineSegment> extractLines(const std::vector<CellCluster>& clusters, const LineExtractionParams& params) {
  std::vector<LineSegment> segments;
  std::vector<const CellCluster*> leftovers;
  for (const auto& cluster : clusters) {
    LineFit2D fit = fitLine(cluster.points);
    if (acceptable(fit, params)) {
      segments.push_back({fit, cluster.points});
    } else if (fit.length() >= params.min_length_m) {
      splitCluster(cluster.points, params, &segments);
    } else {
      leftovers.push_back(&cluster);
    }
  }
  // A short piece lying on a line (a row's first metre before a gap) belongs to that line.
  for (const CellCluster* piece : leftovers) {
    for (auto& segment : segments) {
      const auto& fit = segment.fit;
      const bool on_line = std::all_of(piece->points.begin(), piece->points.end(), [&](const Eigen::Vector2d& p) {
        const double s = fit.along(p);
        return std::abs(fit.signedDistance(p)) <= params.merge_offset_m && s >= fit.s_min - 2.0 * params.max_gap_m &&
               s <= fit.s_max + 2.0 * params.max_gap_m;
      });
      if (!on_line) continue;
      segment.points.insert(segment.points.end(), piece->points.begin(), piece->points.end());
      segment.fit = fitLine(segment.points);
      break;
    }
  }
  // Merge collinear pieces until nothing changes (the number of lines in a map is small).
  bool merged = true;
  while (merged) {
    merged = false;
    for (std::size_t i = 0; i < segments.size() && !merged; ++i) {
      for (std::size_t j = i + 1; j < segments.size() && !merged; ++j) {
        if (!collinear(segments[i].fit, segments[j].fit, params)) continue;
        segments[i].points.insert(segments[i].points.end(), segments[j].points.begin(), segments[j].points.end());
        segments[i].fit = fitLine(segments[i].points);
        segments.erase(segments.begin() + static_cast<std::ptrdiff_t>(j));
        merged = true;
      }
    }
  }
  return segments;
}

}  // namespace greenhouse_rail_nav
