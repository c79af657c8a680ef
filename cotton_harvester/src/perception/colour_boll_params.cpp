#include "cotton_harvester/perception/colour_boll_params.h"

#include <sstream>

namespace cotton_harvester {
namespace perception {

std::string validate(const ColourBollParams& p) {
  std::ostringstream error;
  if (p.value_min < 0 || p.value_min > 255) error << "value_min must be in [0, 255] (got " << p.value_min << "); ";
  if (p.saturation_max < 0 || p.saturation_max > 255)
    error << "saturation_max must be in [0, 255] (got " << p.saturation_max << "); ";
  if (!(p.value_contrast >= 1.0 && p.value_contrast <= 5.0))
    error << "value_contrast must be in [1, 5] (got " << p.value_contrast << "); ";
  if (p.value_floor < 0 || p.value_floor > p.value_min)
    error << "value_floor must be in [0, value_min] (got " << p.value_floor << "); ";
  if (!(p.opening_fraction >= 0.0 && p.opening_fraction <= 2.0))
    error << "opening_fraction must be in [0, 2] (got " << p.opening_fraction << "); ";
  if (!(p.closing_fraction >= 0.0 && p.closing_fraction <= 2.0))
    error << "closing_fraction must be in [0, 2] (got " << p.closing_fraction << "); ";
  if (!(p.partial_min_visible >= 0.0 && p.partial_min_visible <= 1.0))
    error << "partial_min_visible must be in [0, 1] (got " << p.partial_min_visible << "); ";
  if (!(p.circle_max_rms_fraction > 0.0 && p.circle_max_rms_fraction <= 1.0))
    error << "circle_max_rms_fraction must be in (0, 1] (got " << p.circle_max_rms_fraction << "); ";
  if (!(p.circle_min_arc_deg >= 0.0 && p.circle_min_arc_deg <= 360.0))
    error << "circle_min_arc_deg must be in [0, 360] (got " << p.circle_min_arc_deg << "); ";
  if (!(p.partial_min_fraction >= 0.0 && p.partial_min_fraction <= 1.0))
    error << "partial_min_fraction must be in [0, 1] (got " << p.partial_min_fraction << "); ";
  if (!(p.min_visible_fraction > 0.0 && p.min_visible_fraction <= 1.0))
    error << "min_visible_fraction must be in (0, 1] (got " << p.min_visible_fraction << "); ";
  if (p.max_cluster_bolls < 1 || p.max_cluster_bolls > 100)
    error << "max_cluster_bolls must be in [1, 100] (got " << p.max_cluster_bolls << "); ";
  if (!(p.min_circularity >= 0.0 && p.min_circularity <= 1.0))
    error << "min_circularity must be in [0, 1] (got " << p.min_circularity << "); ";
  if (!(p.min_solidity >= 0.0 && p.min_solidity <= 1.0))
    error << "min_solidity must be in [0, 1] (got " << p.min_solidity << "); ";
  if (!(p.max_aspect_ratio >= 1.0)) error << "max_aspect_ratio must be >= 1 (got " << p.max_aspect_ratio << "); ";
  if (!(p.split_neck_ratio >= 0.0 && p.split_neck_ratio <= 1.0))
    error << "split_neck_ratio must be in [0, 1] (got " << p.split_neck_ratio << "); ";
  return error.str();
}

}  // namespace perception
}  // namespace cotton_harvester
