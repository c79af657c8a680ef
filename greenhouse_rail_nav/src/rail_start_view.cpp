#include "greenhouse_rail_nav/rail_start_view.h"

#include <cmath>

namespace greenhouse_rail_nav {

bool floorSeen(const std::vector<float>& floor_cells, const Eigen::Vector2d& q, const RailDetectorParams& p) {
  const int cols = static_cast<int>(std::ceil(2.0 * p.crop_y_max_m / kFloorBinM));
  const int rows = static_cast<int>(std::ceil((p.crop_x_max_m - p.crop_x_min_m) / kFloorBinM));
  const int col = static_cast<int>(std::floor((q.y() + p.crop_y_max_m) / kFloorBinM));
  const int row = static_cast<int>(std::floor((q.x() - p.crop_x_min_m) / kFloorBinM));
  if (col < 0 || col >= cols || row < 0 || row >= rows) return false;
  const std::size_t cell = static_cast<std::size_t>(row * cols + col);
  return cell < floor_cells.size() && floor_cells[cell] > 0.0f;
}

RailStartView railStartView(const std::vector<RailLine>& rails, const std::vector<float>& floor_cells,
                            const std::optional<CloudProjection>& projection, const Eigen::Isometry3d& camera_in_base,
                            const RailDetectorParams& p) {
  RailStartView view;
  const Eigen::Isometry3d base_to_camera = camera_in_base.inverse();
  auto in_image = [&](const Eigen::Vector2d& q, double z) {
    return !projection || projection->inImage(base_to_camera * Eigen::Vector3d(q.x(), q.y(), z), p.image_margin_px);
  };
  for (const RailLine& rail : rails) {
    const Eigen::Vector2d start = rail.fit.centroid + rail.near_end * rail.fit.direction;
    if (!in_image(start - p.start_view_margin_m * rail.fit.direction, rail.height_m)) {
      view.seen = false;
      view.why = "the rails are cut by the image border";
      continue;
    }
    bool floor_in_image = false, floor_before = false;
    for (const double back : {p.start_view_margin_m + 0.5 * kFloorBinM, p.start_view_margin_m + 1.5 * kFloorBinM}) {
      const Eigen::Vector2d cell = start - back * rail.fit.direction;
      if (!in_image(cell, 0.0)) continue;
      floor_in_image = true;
      floor_before = floor_before || floorSeen(floor_cells, cell, p);
    }
    if (floor_in_image && !floor_before) {
      view.seen = false;
      view.why = "no floor seen just before it";
    }
  }
  return view;
}

}  // namespace greenhouse_rail_nav
