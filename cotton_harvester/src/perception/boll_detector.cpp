#include "cotton_harvester/perception/boll_detector.h"

#include <cmath>
#include <sstream>

namespace cotton_harvester {
namespace perception {

std::string validate(const BollGeometry& g) {
  std::ostringstream error;
  if (!(std::isfinite(g.camera_height_m) && g.camera_height_m > 0.0 && g.camera_height_m < 20.0))
    error << "camera_height_m must be in (0, 20) [m] (got " << g.camera_height_m << "); ";
  if (!(g.boll_radius_min_m > 0.0 && g.boll_radius_max_m >= g.boll_radius_min_m && g.boll_radius_max_m < 0.5))
    error << "boll_radius_min_m/boll_radius_max_m must satisfy 0 < min <= max < 0.5 [m] (got " << g.boll_radius_min_m
          << ", " << g.boll_radius_max_m << "); ";
  if (!(g.boll_radius_typical_m >= g.boll_radius_min_m && g.boll_radius_typical_m <= g.boll_radius_max_m))
    error << "boll_radius_typical_m must lie in [boll_radius_min_m, boll_radius_max_m] (got " << g.boll_radius_typical_m
          << "); ";
  if (!(g.boll_height_min_m >= 0.0 && g.boll_height_max_m >= g.boll_height_min_m &&
        g.boll_height_max_m + g.boll_radius_max_m < g.camera_height_m))
    error << "boll_height_min_m/boll_height_max_m must satisfy 0 <= min <= max and the highest boll below the camera "
             "(got "
          << g.boll_height_min_m << ", " << g.boll_height_max_m << " with camera_height_m " << g.camera_height_m
          << "); ";
  return error.str();
}

PixelRadiusRange bollRadiusPx(const BollGeometry& g, double focal_px) {
  PixelRadiusRange range;
  range.min_px = focal_px * g.boll_radius_min_m / (g.camera_height_m - g.boll_height_min_m);
  range.max_px = focal_px * g.boll_radius_max_m / (g.camera_height_m - g.boll_height_max_m - g.boll_radius_max_m);
  return range;
}

}  // namespace perception
}  // namespace cotton_harvester
