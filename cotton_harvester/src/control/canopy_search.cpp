#include "cotton_harvester/control/canopy_search.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

namespace cotton_harvester {
namespace control {

std::string CanopySearchParams::check() const {
  const std::pair<const char*, double> positive[] = {{"strip_half_m", strip_half_m},
                                                     {"boll_radius_m", boll_radius_m},
                                                     {"layer_m", layer_m},
                                                     {"housing_height_m", housing_height_m},
                                                     {"effector_half_m", effector_half_m}};
  for (const auto& [key, v] : positive)
    if (!(v > 0.0) || !std::isfinite(v)) return std::string(key) + ": expected > 0";
  if (!(min_cover_fraction > 0.0 && min_cover_fraction <= 1.0)) return "min_cover_fraction: expected within (0, 1]";
  if (!(above_layer_m >= 0.0) || !std::isfinite(above_layer_m)) return "above_layer_m: expected >= 0";
  if (!(push_m >= 0.0) || !std::isfinite(push_m)) return "push_m: expected >= 0";
  if (max_passes < 1) return "max_passes: expected >= 1";
  return "";
}

std::optional<CanopyLayer> nextCanopyLayer(const CloudView& cloud, double fx, double strip_y_m, double x_min_m,
                                           double x_max_m, double below_depth_m, double max_depth_m,
                                           const CanopySearchParams& params) {
  if (!cloud.data || cloud.rows <= 0 || cloud.cols <= 0) return std::nullopt;
  if (!(fx > 0.0) || !std::isfinite(strip_y_m) || !std::isfinite(x_min_m) || !std::isfinite(x_max_m) ||
      !std::isfinite(below_depth_m) || !std::isfinite(max_depth_m))
    return std::nullopt;
  struct P {
    float z, x;
  };
  std::vector<P> points;
  for (int v = 0; v < cloud.rows; v += 2) {
    const std::uint8_t* row = cloud.data + static_cast<std::size_t>(v) * cloud.row_step;
    for (int u = 0; u < cloud.cols; u += 2) {
      const std::uint8_t* point = row + static_cast<std::size_t>(u) * cloud.point_step;
      float x, y, z;
      std::memcpy(&z, point + cloud.z_offset, sizeof(float));
      if (!(z > below_depth_m && z <= max_depth_m)) continue;  // also false for NaN
      std::memcpy(&x, point + cloud.x_offset, sizeof(float));
      std::memcpy(&y, point + cloud.y_offset, sizeof(float));
      if (!(std::abs(y - strip_y_m) <= params.strip_half_m) || !(x >= x_min_m && x <= x_max_m)) continue;
      points.push_back({z, x});
    }
  }
  std::sort(points.begin(), points.end(), [](const P& a, const P& b) { return a.z < b.z; });
  // Slide a window of layer_m down the sorted depths; the first window holding a boll's disc worth of points
  // (4 pixels a sampled point) is the layer.
  std::size_t end = 0;
  for (std::size_t begin = 0; begin < points.size(); ++begin) {
    const double top = points[begin].z;
    while (end < points.size() && points[end].z <= top + params.layer_m) ++end;
    const double disc_px = M_PI * std::pow(fx * params.boll_radius_m / top, 2.0);
    const int count = 4 * static_cast<int>(end - begin);
    if (count < params.min_cover_fraction * disc_px) continue;
    CanopyLayer layer;
    layer.top_m = top;
    layer.sweep_depth_m = top - params.above_layer_m;
    layer.points = count;
    layer.x_min_m = layer.x_max_m = points[begin].x;
    for (std::size_t i = begin; i < end; ++i) {
      layer.x_min_m = std::min<double>(layer.x_min_m, points[i].x);
      layer.x_max_m = std::max<double>(layer.x_max_m, points[i].x);
    }
    return layer;
  }
  return std::nullopt;
}

CanopySearch::CanopySearch(const ArmWorkspace& arm, const CanopySearchParams& params)
    : arm_(arm), params_(params), below_m_(arm.rest_depth_m + params.housing_height_m + 0.01) {}

std::optional<CanopySweep> CanopySearch::next(const CloudView& cloud, double fx) {
  const double zero = arm_.extension_zero_x_m, e = params_.effector_half_m;
  const auto layer = nextCanopyLayer(cloud, fx, arm_.strip_y_m, arm_.extension_min_m + zero - e,
                                     arm_.extension_max_m + zero + e, below_m_, arm_.max_depth_m, params_);
  if (!layer) return std::nullopt;
  const auto ext = [this](double v) { return std::clamp(v, arm_.extension_min_m, arm_.extension_max_m); };
  CanopySweep sweep;
  sweep.depth_m = std::clamp(layer->sweep_depth_m, arm_.rest_depth_m, arm_.max_depth_m);
  sweep.from_extension_m = ext(layer->x_min_m - zero - e - 0.02);
  sweep.to_extension_m = ext(layer->x_max_m - zero + e + params_.push_m);
  below_m_ = sweep.depth_m + params_.housing_height_m;  // what this sweep passes through
  return sweep;
}

double focalFromCloud(const CloudView& cloud) {
  if (!cloud.data || cloud.rows <= 0 || cloud.cols < 8) return 0.0;
  const auto ray = [&](int v, int u, double* x_over_z) {
    const std::uint8_t* point =
        cloud.data + static_cast<std::size_t>(v) * cloud.row_step + static_cast<std::size_t>(u) * cloud.point_step;
    float x, z;
    std::memcpy(&x, point + cloud.x_offset, sizeof(float));
    std::memcpy(&z, point + cloud.z_offset, sizeof(float));
    if (!(z > 0.0f) || !std::isfinite(x)) return false;
    *x_over_z = static_cast<double>(x) / z;
    return true;
  };
  std::vector<double> estimates;
  const int step = std::max(1, cloud.rows / 32);
  for (int v = 0; v < cloud.rows; v += step) {
    // The first and the last point with depth in the row's outer quarters.
    int u0 = -1, u1 = -1;
    double r0 = 0.0, r1 = 0.0;
    for (int u = 0; u < cloud.cols / 4 && u0 < 0; ++u)
      if (ray(v, u, &r0)) u0 = u;
    for (int u = cloud.cols - 1; u >= 3 * cloud.cols / 4 && u1 < 0; --u)
      if (ray(v, u, &r1)) u1 = u;
    if (u0 < 0 || u1 < 0 || !(r1 - r0 > 1e-6)) continue;
    estimates.push_back((u1 - u0) / (r1 - r0));
  }
  if (estimates.size() < 3) return 0.0;
  std::nth_element(estimates.begin(), estimates.begin() + estimates.size() / 2, estimates.end());
  return estimates[estimates.size() / 2];
}

}  // namespace control
}  // namespace cotton_harvester
