#include "greenhouse_rail_nav/rail_detector.h"

#include <algorithm>
#include <cmath>

#include "greenhouse_rail_nav/cloud_projection.h"
#include "greenhouse_rail_nav/depth_median.h"
#include "greenhouse_rail_nav/rail_band.h"
#include "greenhouse_rail_nav/rail_holes.h"
#include "greenhouse_rail_nav/rail_line_candidates.h"
#include "greenhouse_rail_nav/rail_pair_selection.h"
#include "greenhouse_rail_nav/rail_set_layout.h"
#include "greenhouse_rail_nav/rail_start_view.h"

namespace greenhouse_rail_nav {
namespace {

RailLine transformed(const RailLine& rail, const thorvald_base::Pose2D& t) {
  RailLine out = rail;
  out.fit.centroid = t.transformPoint(rail.fit.centroid);
  out.fit.direction = thorvald_base::Pose2D(0, 0, t.yaw).transformPoint(rail.fit.direction);
  return out;
}

/// Empty when the cloud can be searched, else why not.
std::string cloudProblem(const OrganisedCloud& cloud) {
  if (cloud.points.empty()) return "empty cloud";
  if (static_cast<std::size_t>(cloud.width) * static_cast<std::size_t>(cloud.height) != cloud.points.size())
    return "malformed cloud: width x height != number of points";
  return "";
}

/// Fills `out` with the chosen rail set, moved by the mount correction, and with the paper's output: base_link in
/// the rail frame; x unobserved (and its variance widened) when the rails' start was out of view.
void reportRails(const RailPairChoice& choice, const RailStartView& view, const thorvald_base::Pose2D& mount_correction,
                 const RailDetectorParams& p, RailDetection* out) {
  out->gauge_m = choice.pair.gauge_m;
  out->fit_score = choice.fit_score;
  out->variance = choice.variance;
  out->rail_in_base = mount_correction * choice.pair.rail_in_base;
  out->rails = {transformed(choice.pair.first, mount_correction), transformed(choice.pair.second, mount_correction)};
  out->base_in_rail = out->rail_in_base.inverse();
  out->status = RailDetection::Status::kFound;
  out->reason = "rails found: gauge " + formatMetres(out->gauge_m, 3) + " m, r " + formatMetres(out->fit_score, 4);
  if (!view.seen) {
    out->status = RailDetection::Status::kFoundXUnobserved;
    out->variance[0] = std::max(out->variance[0], p.unobserved_sigma_x_m * p.unobserved_sigma_x_m);
    out->reason += "; rails' start out of view (" + view.why + "): x " + formatMetres(out->base_in_rail.x, 3) +
                   " m is where they enter the image, the start is nearer";
  }
}

}  // namespace

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

RailDetection RailDetector::detect(const OrganisedCloud& raw_cloud, const Eigen::Isometry3d& camera_in_base,
                                   const thorvald_base::Pose2D& mount_correction, RailFitMethod method) const {
  RailDetection out;
  const auto& p = params_;
  out.reason = cloudProblem(raw_cloud);
  if (!out.reason.empty()) {
    out.status = RailDetection::Status::kBadInput;
    return out;
  }
  // 0. The depth image's range noise, smoothed along the rays (edges kept), when configured.
  OrganisedCloud smoothed;
  if (p.depth_median_px > 1) smoothed = medianAlongRays(raw_cloud, p.depth_median_px);
  const OrganisedCloud& cloud = p.depth_median_px > 1 ? smoothed : raw_cloud;
  const auto projection = CloudProjection::fromCloud(cloud);
  std::vector<float> floor_cells;
  out = search(cloud, cloud, projection, camera_in_base, mount_correction, method, &floor_cells);
  if (out.found() || out.status == RailDetection::Status::kBadInput || !(p.pipe_hole_height_m > 0.0) || !projection)
    return out;
  // Shiny pipes without depth: the same search on the holes laid on the pipes' height (the floor seen as before).
  const OrganisedCloud holes = holesOnPlane(raw_cloud, *projection, camera_in_base, p.pipe_hole_height_m);
  RailDetection from_holes = search(holes, cloud, projection, camera_in_base, mount_correction, method, &floor_cells);
  if (!from_holes.found()) {
    out.reason += "; in the pipes' depth holes: " + from_holes.reason;
    return out;
  }
  from_holes.reason += " (from the pipes' depth holes)";
  from_holes.finite_points = out.finite_points;
  return from_holes;
}

RailDetection RailDetector::search(const OrganisedCloud& searched, const OrganisedCloud& depth,
                                   const std::optional<CloudProjection>& projection,
                                   const Eigen::Isometry3d& camera_in_base,
                                   const thorvald_base::Pose2D& mount_correction, RailFitMethod method,
                                   std::vector<float>* floor_cells) const {
  RailDetection out;
  const auto& p = params_;
  // 1. The rails' height band, and where the floor was seen (in the depth points, on the first search).
  RailBand band;
  const bool first = &searched == &depth;
  band.points = cropToRailBand(searched, camera_in_base, &out.finite_points, first ? floor_cells : nullptr, &band.raw);
  out.points_in_band = band.points.size();
  if (out.finite_points == 0 && first) {
    out.status = RailDetection::Status::kBadInput;
    out.reason = "no finite point in " + std::to_string(searched.points.size()) + " points";
    return out;
  }
  if (static_cast<int>(band.points.size()) < p.min_cluster_points) {
    out.reason = "only " + std::to_string(band.points.size()) + " points in the rails' height band [" +
                 formatMetres(p.crop_z_min_m, 3) + ", " + formatMetres(p.crop_z_max_m, 3) + "] m";
    return out;
  }
  band.xy = xyOf(band.points);

  // 2. Straight lines that may be rails.
  const bool paper = method == RailFitMethod::kClusterLines;
  const RailLineCandidates candidates = paper ? clusterRailLines(band.points, p) : ransacRailLines(band.points, p);
  out.clusters = candidates.groups;
  out.lines = candidates.lines.size();
  if (candidates.lines.empty()) {
    out.reason = "no straight line among " + std::to_string(out.clusters) + " clusters of " +
                 std::to_string(band.points.size()) + " points in the rails' band";
    return out;
  }
  // 3. Two of them a gauge apart, on their pipes' axes.
  const std::optional<RailPairChoice> choice =
      selectRailPair(candidates.lines, band, paper, camera_in_base.translation(), p, &out.reason);
  if (!choice) return out;
  // 4. Whether their start was in view; 5. the pose.
  const RailStartView view =
      railStartView({choice->pair.first, choice->pair.second}, *floor_cells, projection, camera_in_base, p);
  reportRails(*choice, view, mount_correction, p, &out);
  return out;
}

}  // namespace greenhouse_rail_nav
