#include "greenhouse_rail_nav/rail_detector_params.h"

#include <cmath>

namespace greenhouse_rail_nav {

std::string RailDetectorParams::validate() const {
  auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(rail_gauge_m)) return "rail_gauge_m must be > 0 [m]";
  if (!positive(gauge_tolerance_m) || gauge_tolerance_m >= 0.5 * rail_gauge_m)
    return "gauge_tolerance_m must be > 0 and < rail_gauge_m / 2 [m]";
  if (depth_median_px > 1 && depth_median_px % 2 == 0) return "depth_median_px must be odd (or 0: off)";
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

}  // namespace greenhouse_rail_nav
