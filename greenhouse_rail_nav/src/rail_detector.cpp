#include "greenhouse_rail_nav/rail_detector.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>

#include <Eigen/Dense>

#include "greenhouse_rail_nav/cloud_projection.h"
#include "greenhouse_rail_nav/pcl_backend.h"

namespace greenhouse_rail_nav {
namespace {

std::string fmt(double value, int decimals = 3) {
  std::ostringstream s;
  s.setf(std::ios::fixed);
  s.precision(decimals);
  s << value;
  return s.str();
}

/// One point per occupied voxel (the mean of its points), so near, dense parts of a rail do not
/// outweigh far ones and clustering gets fewer points.
std::vector<Eigen::Vector3f> thinToVoxels(const std::vector<Eigen::Vector3f>& points, double voxel) {
  if (voxel <= 0.0 || points.empty()) return points;
  const float inv = static_cast<float>(1.0 / voxel);
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed;
  keyed.reserve(points.size());
  for (std::uint32_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector3f& p = points[i];
    // 21 bits per axis with an offset: +-10 km at 1 cm voxels is far beyond any crop box.
    const auto cell = [&](float v) { return static_cast<std::uint64_t>(std::floor(v * inv) + (1 << 20)) & 0x1FFFFF; };
    keyed.emplace_back((cell(p.x()) << 42) | (cell(p.y()) << 21) | cell(p.z()), i);
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<Eigen::Vector3f> out;
  for (std::size_t i = 0; i < keyed.size();) {
    Eigen::Vector3f sum = Eigen::Vector3f::Zero();
    std::size_t j = i;
    for (; j < keyed.size() && keyed[j].first == keyed[i].first; ++j) sum += points[keyed[j].second];
    out.push_back(sum / static_cast<float>(j - i));
    i = j;
  }
  return out;
}

std::vector<Eigen::Vector2d> xyOf(const std::vector<Eigen::Vector3f>& points, const std::vector<int>& indices) {
  std::vector<Eigen::Vector2d> xy;
  xy.reserve(indices.size());
  for (const int i : indices)
    xy.emplace_back(points[static_cast<std::size_t>(i)].x(), points[static_cast<std::size_t>(i)].y());
  return xy;
}

/// Median z of the given points [m].
double medianHeight(const std::vector<Eigen::Vector3f>& points, const std::vector<int>& indices) {
  std::vector<float> z;
  z.reserve(indices.size());
  for (const int i : indices) z.push_back(points[static_cast<std::size_t>(i)].z());
  if (z.empty()) return 0.0;
  std::nth_element(z.begin(), z.begin() + static_cast<std::ptrdiff_t>(z.size() / 2), z.end());
  return z[z.size() / 2];
}

double lineAngle(const LineFit2D& a, const LineFit2D& b) {
  return std::acos(std::min(1.0, std::abs(a.direction.dot(b.direction))));
}

RailLine transformed(const RailLine& rail, const thorvald_base::Pose2D& t) {
  RailLine out = rail;
  out.fit.centroid = t.transformPoint(rail.fit.centroid);
  out.fit.direction = thorvald_base::Pose2D(0, 0, t.yaw).transformPoint(rail.fit.direction);
  return out;
}

constexpr double kFloorBinM = 0.05;

}  // namespace

std::string RailDetectorParams::validate() const {
  auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(rail_gauge_m)) return "rail_gauge_m must be > 0 [m]";
  if (!positive(gauge_tolerance_m) || gauge_tolerance_m >= 0.5 * rail_gauge_m)
    return "gauge_tolerance_m must be > 0 and < rail_gauge_m / 2 [m]";
  if (!(std::isfinite(crop_z_min_m) && std::isfinite(crop_z_max_m) && crop_z_min_m < crop_z_max_m))
    return "crop_z_min_m must be < crop_z_max_m [m]";
  if (!(std::isfinite(crop_x_min_m) && std::isfinite(crop_x_max_m) && crop_x_min_m < crop_x_max_m))
    return "crop_x_min_m must be < crop_x_max_m [m]";
  if (!positive(crop_y_max_m)) return "crop_y_max_m must be > 0 [m]";
  if (!(std::isfinite(voxel_size_m) && voxel_size_m >= 0.0 && voxel_size_m < cluster_tolerance_m))
    return "voxel_size_m must be >= 0 and < cluster_tolerance_m [m]";
  if (!positive(cluster_tolerance_m)) return "cluster_tolerance_m must be > 0 [m]";
  if (min_cluster_points < 3) return "min_cluster_points must be >= 3";
  if (max_cluster_points < min_cluster_points) return "max_cluster_points must be >= min_cluster_points";
  if (!positive(min_line_length_m)) return "min_line_length_m must be > 0 [m]";
  if (!(min_linearity > 0.0 && min_linearity < 1.0)) return "min_linearity must be in (0, 1)";
  if (!(min_partner_coverage >= 0.0 && min_partner_coverage <= 1.0)) return "min_partner_coverage must be in [0, 1]";
  if (!positive(height_tolerance_m)) return "height_tolerance_m must be > 0 [m]";
  if (!positive(parallel_tolerance_rad)) return "parallel_tolerance_rad must be > 0 [rad]";
  if (!(max_abs_yaw_rad > 0.0 && max_abs_yaw_rad < M_PI / 2)) return "max_abs_yaw_rad must be in (0, pi/2) [rad]";
  if (!positive(max_lateral_offset_m)) return "max_lateral_offset_m must be > 0 [m]";
  if (!positive(rail_trim_m)) return "rail_trim_m must be > 0 [m]";
  if (!positive(ransac_distance_m)) return "ransac_distance_m must be > 0 [m]";
  if (ransac_max_lines < 2) return "ransac_max_lines must be >= 2";
  if (ransac_iterations < 1) return "ransac_iterations must be >= 1";
  if (!positive(sigma_x_m) || !positive(sigma_y_m) || !positive(sigma_yaw_rad))
    return "sigma_x_m, sigma_y_m and sigma_yaw_rad must be > 0";
  if (!(std::isfinite(start_view_margin_m) && start_view_margin_m >= 0.0 && start_view_margin_m < 1.0))
    return "start_view_margin_m must be in [0, 1) [m]";
  if (!positive(unobserved_sigma_x_m)) return "unobserved_sigma_x_m must be > 0 [m]";
  if (!(std::isfinite(pipe_radius_m) && pipe_radius_m >= 0.0 && pipe_radius_m < 0.2))
    return "pipe_radius_m must be in [0, 0.2) [m]";
  if (!(std::isfinite(image_margin_px) && image_margin_px >= 0.0 && image_margin_px < 100.0))
    return "image_margin_px must be in [0, 100) [px]";
  return "";
}

std::vector<Eigen::Vector3f> RailDetector::cropToRailBand(const OrganisedCloud& cloud,
                                                          const Eigen::Isometry3d& camera_in_base,
                                                          std::size_t* finite_points, std::vector<float>* floor_cells,
                                                          std::vector<Eigen::Vector3f>* raw_band) const {
  const Eigen::Matrix3f rot = camera_in_base.linear().cast<float>();
  const Eigen::Vector3f trans = camera_in_base.translation().cast<float>();
  const auto& p = params_;
  std::vector<Eigen::Vector3f> band;
  std::size_t finite = 0;
  const int cols = static_cast<int>(std::ceil(2.0 * p.crop_y_max_m / kFloorBinM));
  const int rows = static_cast<int>(std::ceil((p.crop_x_max_m - p.crop_x_min_m) / kFloorBinM));
  if (floor_cells) floor_cells->assign(static_cast<std::size_t>(cols * rows), 0.0f);
  for (const auto& point : cloud.points) {
    if (!point.allFinite()) continue;
    ++finite;
    const Eigen::Vector3f b = rot * point + trans;
    if (floor_cells && b.z() < p.crop_z_min_m && b.z() > -0.05f && std::abs(b.y()) < p.crop_y_max_m &&
        b.x() >= p.crop_x_min_m && b.x() < p.crop_x_max_m) {
      const int col = std::clamp(static_cast<int>((b.y() + p.crop_y_max_m) / kFloorBinM), 0, cols - 1);
      const int row = std::clamp(static_cast<int>((b.x() - p.crop_x_min_m) / kFloorBinM), 0, rows - 1);
      (*floor_cells)[static_cast<std::size_t>(row * cols + col)] = 1.0f;
    }
    if (b.z() >= p.crop_z_min_m && b.z() <= p.crop_z_max_m && b.x() >= p.crop_x_min_m && b.x() <= p.crop_x_max_m &&
        std::abs(b.y()) <= p.crop_y_max_m) {
      band.push_back(b);
    }
  }
  if (finite_points) *finite_points = finite;
  if (raw_band) *raw_band = band;
  return thinToVoxels(band, p.voxel_size_m);
}

RailDetection RailDetector::detect(const OrganisedCloud& cloud, const Eigen::Isometry3d& camera_in_base,
                                   const thorvald_base::Pose2D& mount_correction, RailFitMethod method) const {
  RailDetection out;
  const auto& p = params_;
  if (cloud.points.empty()) {
    out.status = RailDetection::Status::kBadInput;
    out.reason = "empty cloud";
    return out;
  }
  if (static_cast<std::size_t>(cloud.width) * static_cast<std::size_t>(cloud.height) != cloud.points.size()) {
    out.status = RailDetection::Status::kBadInput;
    out.reason = "malformed cloud: width x height != number of points";
    return out;
  }
  std::vector<float> floor_cells;
  std::vector<Eigen::Vector3f> raw_band;
  const auto band = cropToRailBand(cloud, camera_in_base, &out.finite_points, &floor_cells, &raw_band);
  out.points_in_band = band.size();
  if (out.finite_points == 0) {
    out.status = RailDetection::Status::kBadInput;
    out.reason = "no finite point in " + std::to_string(cloud.points.size()) + " points";
    return out;
  }
  if (static_cast<int>(band.size()) < p.min_cluster_points) {
    out.reason = "only " + std::to_string(band.size()) + " points in the rails' height band [" + fmt(p.crop_z_min_m) +
                 ", " + fmt(p.crop_z_max_m) + "] m";
    return out;
  }
  std::vector<Eigen::Vector2d> band_xy;
  band_xy.reserve(band.size());
  for (const auto& b : band) band_xy.emplace_back(b.x(), b.y());

  std::vector<RailLine> lines;
  if (method == RailFitMethod::kClusterLines) {
    const auto clusters = euclideanClusters(band, p.cluster_tolerance_m, p.min_cluster_points, p.max_cluster_points);
    out.clusters = clusters.size();
    for (const auto& cluster : clusters) {
      const auto xy = xyOf(band, cluster);
      const RailLine raw = makeRailLine(xy);
      const double heading = std::atan2(raw.fit.direction.y(), raw.fit.direction.x());
      if (raw.fit.length() >= p.min_line_length_m && raw.fit.linearity >= p.min_linearity &&
          std::abs(heading) <= p.max_abs_yaw_rad) {
        lines.push_back(trimRailLine(xy, raw, p.rail_trim_m));
        lines.back().height_m = medianHeight(band, cluster);
      }
    }
    std::sort(lines.begin(), lines.end(),
              [](const RailLine& a, const RailLine& b) { return a.fit.linearity > b.fit.linearity; });
  } else {
    const auto found =
        ransacLines(band, p.ransac_distance_m, p.ransac_max_lines, p.min_cluster_points, p.ransac_iterations);
    out.clusters = found.size();
    for (const auto& line : found) {
      // Keep RANSAC's own model: its direction, positioned at the inliers' mean, extents from the inliers.
      const auto xy = xyOf(band, line.inliers);
      RailLine rail = makeRailLine(xy);
      const Eigen::Vector2d d = Eigen::Vector2d(line.direction.x(), line.direction.y());
      if (d.norm() < 0.5) continue;  // a vertical line is no rail
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
      if (rail.fit.length() >= p.min_line_length_m && std::abs(heading) <= p.max_abs_yaw_rad) lines.push_back(rail);
    }
    std::sort(lines.begin(), lines.end(), [](const RailLine& a, const RailLine& b) { return a.points > b.points; });
  }
  out.lines = lines.size();
  if (lines.empty()) {
    out.reason = "no straight line among " + std::to_string(out.clusters) + " clusters of " +
                 std::to_string(band.size()) + " points in the rails' band";
    return out;
  }
  if (!pairFromLines(lines, band, band_xy, method == RailFitMethod::kClusterLines, camera_in_base.translation(),
                     raw_band, &out))
    return out;

  // Is the rails' start in view? For each rail:
  // 1. the point start_view_margin_m before its start must lie inside the image: where the rails are cut by
  //    the image border, the floor beside the cut may still be seen, but the start is not;
  // 2. where the floor just before the start (two 5 cm cells on the rail's line) lies inside the image, floor
  //    must have been seen there: else something (a leaf, a dropout) hides the start, which may be nearer.
  // Without a projection (a cloud that is no pinhole image) the floor alone decides.
  bool start_seen = true;
  std::string why_unseen;
  const int cols = static_cast<int>(std::ceil(2.0 * p.crop_y_max_m / kFloorBinM));
  const int rows = static_cast<int>(std::ceil((p.crop_x_max_m - p.crop_x_min_m) / kFloorBinM));
  auto floor_seen = [&](const Eigen::Vector2d& q) {
    const int col = static_cast<int>(std::floor((q.y() + p.crop_y_max_m) / kFloorBinM));
    const int row = static_cast<int>(std::floor((q.x() - p.crop_x_min_m) / kFloorBinM));
    return col >= 0 && col < cols && row >= 0 && row < rows &&
           floor_cells[static_cast<std::size_t>(row * cols + col)] > 0.0f;
  };
  const auto projection = CloudProjection::fromCloud(cloud);
  const Eigen::Isometry3d base_to_camera = camera_in_base.inverse();
  auto in_image = [&](const Eigen::Vector2d& q, double z) {
    return !projection || projection->inImage(base_to_camera * Eigen::Vector3d(q.x(), q.y(), z), p.image_margin_px);
  };
  for (const RailLine& rail : out.rails) {
    const Eigen::Vector2d start = rail.fit.centroid + rail.near_end * rail.fit.direction;
    if (!in_image(start - p.start_view_margin_m * rail.fit.direction, rail.height_m)) {
      start_seen = false;
      why_unseen = "the rails are cut by the image border";
      continue;
    }
    bool floor_in_image = false, floor_before = false;
    for (const double back : {p.start_view_margin_m + 0.5 * kFloorBinM, p.start_view_margin_m + 1.5 * kFloorBinM}) {
      const Eigen::Vector2d cell = start - back * rail.fit.direction;
      if (!in_image(cell, 0.0)) continue;
      floor_in_image = true;
      floor_before = floor_before || floor_seen(cell);
    }
    if (floor_in_image && !floor_before) {
      start_seen = false;
      why_unseen = "no floor seen just before it";
    }
  }

  // Mount correction, then the paper's output: base_link in the rail frame.
  out.rail_in_base = mount_correction * out.rail_in_base;
  for (auto& rail : out.rails) rail = transformed(rail, mount_correction);
  out.base_in_rail = out.rail_in_base.inverse();
  out.status = RailDetection::Status::kFound;
  out.reason = "rails found: gauge " + fmt(out.gauge_m) + " m, r " + fmt(out.fit_score, 4);
  if (!start_seen) {
    out.status = RailDetection::Status::kFoundXUnobserved;
    out.variance[0] = std::max(out.variance[0], p.unobserved_sigma_x_m * p.unobserved_sigma_x_m);
    out.reason += "; rails' start out of view (" + why_unseen + "): x " + fmt(out.base_in_rail.x) +
                  " m is where they enter the image, the start is nearer";
  }
  return out;
}

RailLine RailDetector::axisLine(const RailLine& rail, const Eigen::Vector3d& camera_xyz,
                                const std::vector<Eigen::Vector3f>& raw_band) const {
  const double r = params_.pipe_radius_m;
  if (r <= 0.0) return rail;
  const Eigen::Vector2d left(-rail.fit.direction.y(), rail.fit.direction.x());
  // Start: the mean offset of the visible half of a cylinder sampled by projected area. In the plane across
  // the pipe the camera sits at lateral distance h and height v above the pipe's centre; that mean lies
  // pi/4 * r * cos(elevation) nearer the camera than the axis.
  const double h = rail.fit.signedDistance(camera_xyz.head<2>());
  const double v = camera_xyz.z() - (rail.height_m - 0.5 * r);
  const double cos_elevation = std::abs(h) / std::max(1e-6, std::hypot(h, v));
  const double model_offset = -(h >= 0.0 ? 1.0 : -1.0) * M_PI / 4.0 * r * cos_elevation;
  RailLine out = rail;
  out.fit.centroid += model_offset * left;

  // Circle of radius r across the rail, fitted to the raw points near the line (lateral offset d, height z):
  // Gauss-Newton on (|q - c| - r), points weighted by 1 / range^4 (active-stereo depth noise grows with
  // range^2), points more than 8 mm off the circle dropped after the first steps (leaves, flying pixels).
  std::vector<Eigen::Vector2d> q;
  std::vector<double> w;
  const Eigen::Vector3d cam = camera_xyz;
  for (const auto& b : raw_band) {
    const Eigen::Vector2d xy(b.x(), b.y());
    const double d = rail.fit.signedDistance(xy), s = rail.fit.along(xy);
    if (std::abs(d) > r + 0.015 || s < rail.fit.s_min - 0.02 || s > rail.fit.s_max + 0.02) continue;
    const double range = std::max(0.3, (b.cast<double>() - cam).norm());
    q.emplace_back(d, b.z());
    w.push_back(1.0 / (range * range * range * range));
  }
  if (q.size() < 20) return out;
  Eigen::Vector2d c(model_offset, rail.height_m - 0.5 * r);
  for (int iteration = 0; iteration < 12; ++iteration) {
    const double cutoff = iteration < 3 ? 0.03 : 0.008;
    Eigen::Matrix2d jtj = Eigen::Matrix2d::Zero();
    Eigen::Vector2d jte = Eigen::Vector2d::Zero();
    std::size_t used = 0;
    for (std::size_t i = 0; i < q.size(); ++i) {
      const Eigen::Vector2d diff = q[i] - c;
      const double dist = diff.norm();
      const double e = dist - r;
      if (dist < 1e-6 || std::abs(e) > cutoff) continue;
      const Eigen::Vector2d j = -diff / dist;
      jtj += w[i] * j * j.transpose();
      jte += w[i] * j * e;
      ++used;
    }
    if (used < 20 || jtj.determinant() <= 1e-12 * jtj.trace() * jtj.trace()) return out;
    const Eigen::Vector2d step = -jtj.ldlt().solve(jte);
    c += step;
    if (!c.allFinite() || std::abs(c.x()) > 2.0 * r) return out;  // diverged: keep the model's offset
    if (step.norm() < 1e-5 && iteration >= 4) break;
  }
  out.fit.centroid = rail.fit.centroid + c.x() * left;
  return out;
}

bool RailDetector::pairFromLines(const std::vector<RailLine>& lines, const std::vector<Eigen::Vector3f>& band,
                                 const std::vector<Eigen::Vector2d>& band_xy, bool search_points_for_partner,
                                 const Eigen::Vector3d& camera_xyz, const std::vector<Eigen::Vector3f>& raw_band,
                                 RailDetection* out) const {
  const auto& p = params_;
  std::string why = "no rail at " + fmt(p.rail_gauge_m) + " +- " + fmt(p.gauge_tolerance_m) + " m beside any of " +
                    std::to_string(lines.size()) + " straight lines";
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const RailLine& best = lines[i];
    // Partner among the other lines: parallel and a gauge away.
    const RailLine* partner = nullptr;
    double partner_error = p.gauge_tolerance_m;
    for (std::size_t j = 0; j < lines.size(); ++j) {
      if (j == i || lineAngle(best.fit, lines[j].fit) > p.parallel_tolerance_rad ||
          std::abs(lines[j].height_m - best.height_m) > p.height_tolerance_m)
        continue;
      const double error = std::abs(std::abs(best.fit.signedDistance(lines[j].fit.centroid)) - p.rail_gauge_m);
      if (error <= partner_error) {
        partner_error = error;
        partner = &lines[j];
      }
    }
    RailLine searched;
    if (!partner && search_points_for_partner) {
      // The partner's cluster may be broken up or merged with leaves: look at the raw band points in a
      // strip a gauge away on either side, and fit the rail there.
      for (const double side : {-1.0, 1.0}) {
        std::vector<int> strip;
        for (std::size_t k = 0; k < band_xy.size(); ++k) {
          if (std::abs(best.fit.signedDistance(band_xy[k]) - side * p.rail_gauge_m) <= p.gauge_tolerance_m)
            strip.push_back(static_cast<int>(k));
        }
        if (static_cast<int>(strip.size()) < p.min_cluster_points) continue;
        const RailLine first = makeRailLine(xyOf(band, strip));
        std::vector<int> close;  // second pass: only points near the fitted rail
        for (const int k : strip)
          if (std::abs(first.fit.signedDistance(band_xy[static_cast<std::size_t>(k)])) <= 0.5 * p.gauge_tolerance_m)
            close.push_back(k);
        if (static_cast<int>(close.size()) < p.min_cluster_points) continue;
        const auto close_xy = xyOf(band, close);
        RailLine candidate = trimRailLine(close_xy, makeRailLine(close_xy), p.rail_trim_m);
        candidate.height_m = medianHeight(band, close);
        std::vector<Eigen::Vector2d> on_rail;
        for (const auto& q : close_xy)
          if (std::abs(candidate.fit.signedDistance(q)) <= 0.5 * p.rail_trim_m) on_rail.push_back(q);
        if (lineCoverage(on_rail, candidate.fit, 0.05) < p.min_partner_coverage) continue;
        if (static_cast<int>(candidate.points) < p.min_cluster_points || candidate.fit.length() < p.min_line_length_m ||
            lineAngle(best.fit, candidate.fit) > p.parallel_tolerance_rad ||
            std::abs(candidate.height_m - best.height_m) > p.height_tolerance_m)
          continue;
        if (!partner || candidate.points > searched.points) {
          searched = candidate;
          partner = &searched;
        }
      }
    }
    if (!partner) continue;
    const RailPair pair = makeRailPair(axisLine(best, camera_xyz, raw_band), axisLine(*partner, camera_xyz, raw_band));
    const thorvald_base::Pose2D base_in_rail = pair.rail_in_base.inverse();
    if (std::abs(base_in_rail.y) > p.max_lateral_offset_m) {
      why = "rail pair found " + fmt(base_in_rail.y) + " m to the side (limit " + fmt(p.max_lateral_offset_m) +
            " m): a neighbouring rail set";
      continue;
    }
    out->rail_in_base = pair.rail_in_base;
    out->gauge_m = pair.gauge_m;
    out->fit_score = best.fit.linearity;
    out->rails = {pair.first, pair.second};
    // Variances: the configured floors plus what the fit residuals say.
    double var_yaw_fit = 0.0, var_offset_fit = 0.0;
    for (const RailLine* r : {&pair.first, &pair.second}) {
      const double n = std::max<double>(2.0, static_cast<double>(r->points));
      const double len = std::max(r->fit.length(), 1e-3);
      var_yaw_fit += r->fit.rms_residual * r->fit.rms_residual / (n * len * len / 12.0) / 4.0;
      var_offset_fit += r->fit.rms_residual * r->fit.rms_residual / n / 4.0;
    }
    const double lever = std::abs(base_in_rail.x);
    out->variance = {p.sigma_x_m * p.sigma_x_m + p.voxel_size_m * p.voxel_size_m,
                     p.sigma_y_m * p.sigma_y_m + var_offset_fit + lever * lever * var_yaw_fit,
                     p.sigma_yaw_rad * p.sigma_yaw_rad + var_yaw_fit};
    return true;
  }
  out->reason = why;
  return false;
}

}  // namespace greenhouse_rail_nav
