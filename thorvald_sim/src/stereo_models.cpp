#include "thorvald_sim/stereo_models.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>

#include "pixel_noise.h"

namespace thorvald_sim {

namespace {

constexpr float kNan = std::numeric_limits<float>::quiet_NaN();

/// An event of probability p against PixelNoise::uniform.
uint32_t below(double p) { return static_cast<uint32_t>(std::clamp(p, 0.0, 1.0) * (1u << PixelNoise::kUniformBits)); }

/// The 4-neighbour of pixel (u, v) whose depth differs most from z, if it differs by more than jump * z; NaN if none.
float edgeNeighbour(const std::vector<float>& z_m, int width, int height, int u, int v, float z, double jump) {
  float best = kNan, best_gap = static_cast<float>(jump * z);
  const int du[4] = {-1, 1, 0, 0}, dv[4] = {0, 0, -1, 1};
  for (int k = 0; k < 4; ++k) {
    const int nu = u + du[k], nv = v + dv[k];
    if (nu < 0 || nv < 0 || nu >= width || nv >= height) continue;
    const float zn = z_m[static_cast<size_t>(nv) * width + nu];
    if (!(zn > 0.0f)) continue;
    const float gap = std::fabs(zn - z);
    if (gap > best_gap) best = zn, best_gap = gap;
  }
  return best;
}

}  // namespace

double glintAngle(const Eigen::Vector3d& n, const Eigen::Vector3d& point, const Eigen::Vector3d& centre,
                  const Eigen::Vector3d& axis, const Eigen::Vector3d& camera) {
  const Eigen::Vector3d q = axis.cross(camera - centre);
  const double qn = q.norm();
  if (qn > 1e-9 * std::max(1.0, (camera - centre).norm())) return std::asin(std::min(1.0, std::fabs(n.dot(q) / qn)));
  const Eigen::Vector3d back = (camera - point).normalized();
  return std::acos(std::clamp(n.dot(back), -1.0, 1.0));
}

std::vector<float> applyActiveStereo(const DepthTruth& t, double fx_px, const ActiveStereoModel& m, std::mt19937& rng) {
  const size_t n = static_cast<size_t>(t.width) * t.height;
  std::vector<float> out(n, kNan);
  if (t.z_m.size() != n) return out;
  PixelNoise noise(rng);
  const bool shiny = t.glint_rad.size() == n;
  const uint32_t drop_below = below(m.dropout), fly_below = below(m.flying_probability);
  for (int v = 0; v < t.height; ++v)
    for (int u = 0; u < t.width; ++u) {
      const size_t i = static_cast<size_t>(v) * t.width + u;
      const float z = t.z_m[i];
      if (!(z > 0.0f)) continue;
      const uint64_t draw = noise.next();
      if (z < m.range_min_m || u < m.baseline_m * fx_px / z) continue;  // too near; the left invalid band
      if (shiny && t.glint_rad[i] < m.shiny_band_rad) continue;         // the glint: no pattern to match
      if (PixelNoise::uniform(draw) < drop_below) continue;
      double zz = z;
      const float other = edgeNeighbour(t.z_m, t.width, t.height, u, v, z, m.edge_jump);
      if (other > 0.0f) {
        const uint64_t fly = noise.next();
        if (PixelNoise::uniform(fly) < fly_below)
          zz = z + ((fly >> PixelNoise::kUniformBits) & ((1u << 28) - 1)) * 0x1.0p-28 * (other - z);
      }
      out[i] = static_cast<float>(zz + m.noise_coeff * zz * zz * noise.normal(draw));
    }
  return out;
}

namespace {

/// Pixels whose left-image point the right camera (at +baseline along x) sees: its column there u - fx B / z is in
/// the image and no pixel further right in the row lands left of it (a nearer surface would cover it).
void visibleInRight(const std::vector<float>& z_m, int width, int height, double fxb, std::vector<char>* seen) {
  seen->assign(z_m.size(), 0);
  for (int v = 0; v < height; ++v) {
    double min_right = std::numeric_limits<double>::infinity();
    for (int u = width - 1; u >= 0; --u) {
      const size_t i = static_cast<size_t>(v) * width + u;
      const float z = z_m[i];
      if (!(z > 0.0f)) continue;
      const double xr = u - fxb / z;
      (*seen)[i] = xr >= 0.0 && !(min_right < xr - 1e-6);
      min_right = std::min(min_right, xr);
    }
  }
}

/// Pixels with texture to match: the grey level's std dev over the window (clipped at the image's border) at least
/// min_sigma, no channel saturated. With s = r + g + b (the grey level times 3), the window's n pixels, S = sum s and
/// Q = sum s^2 (exact integers, summed by columns and slid along the row): var = (n Q - S^2) / (9 n^2).
void textured(const std::vector<uint8_t>& rgb, int width, int height, const PassiveStereoModel& m,
              PassiveStereoScratch* w) {
  const size_t n = static_cast<size_t>(width) * height;
  const int half = std::max(0, m.texture_window_px / 2);
  const double min_var9 = 9.0 * m.min_texture_sigma * m.min_texture_sigma;
  std::vector<int64_t>&col_sum = w->col_sum, &col_sq = w->col_sq;  // per column: over the window's rows
  col_sum.assign(width, 0), col_sq.assign(width, 0);
  auto add_row = [&](int v, int sign) {
    const uint8_t* px = &rgb[3 * static_cast<size_t>(v) * width];
    for (int u = 0; u < width; ++u, px += 3) {
      const int64_t s = px[0] + px[1] + px[2];
      col_sum[u] += sign * s, col_sq[u] += sign * s * s;
    }
  };
  for (int v = 0; v < std::min(half, height); ++v) add_row(v, 1);
  w->ok.assign(n, 0);
  for (int v = 0; v < height; ++v) {
    if (v + half < height) add_row(v + half, 1);
    if (v - half - 1 >= 0) add_row(v - half - 1, -1);
    const int64_t rows = std::min(height, v + half + 1) - std::max(0, v - half);
    int64_t sum = 0, sq = 0;  // over columns [u - half, u + half] within the image
    for (int u = 0; u < std::min(half, width); ++u) sum += col_sum[u], sq += col_sq[u];
    const uint8_t* px = &rgb[3 * static_cast<size_t>(v) * width];
    char* ok = &w->ok[static_cast<size_t>(v) * width];
    auto test = [&](int u) {
      if (std::max({px[3 * u], px[3 * u + 1], px[3 * u + 2]}) >= m.saturation_level) return;
      const int64_t cnt = rows * (std::min(width, u + half + 1) - std::max(0, u - half));
      ok[u] = static_cast<double>(cnt * sq - sum * sum) >= min_var9 * static_cast<double>(cnt * cnt);
    };
    // The window's columns come in (u + half) and go out (u - half - 1) only within the image: the row's two ends
    // apart from its middle, where both always do.
    const int mid0 = std::min(width, half + 1), mid1 = std::max(mid0, width - half);
    for (int u = 0; u < mid0; ++u) {
      if (u + half < width) sum += col_sum[u + half], sq += col_sq[u + half];
      test(u);
    }
    const double min_var9_full = min_var9 * static_cast<double>(rows * (2 * half + 1) * rows * (2 * half + 1));
    const int64_t full = rows * (2 * half + 1);
    for (int u = mid0; u < mid1; ++u) {
      sum += col_sum[u + half] - col_sum[u - half - 1], sq += col_sq[u + half] - col_sq[u - half - 1];
      const bool unsaturated = std::max({px[3 * u], px[3 * u + 1], px[3 * u + 2]}) < m.saturation_level;
      ok[u] = unsaturated && static_cast<double>(full * sq - sum * sum) >= min_var9_full;
    }
    for (int u = mid1; u < width; ++u) {
      if (u + half < width) sum += col_sum[u + half], sq += col_sq[u + half];
      sum -= col_sum[u - half - 1], sq -= col_sq[u - half - 1];
      test(u);
    }
  }
}

}  // namespace

std::vector<float> passiveStereoDepth(const std::vector<float>& z_m, const std::vector<uint8_t>& rgb, int width,
                                      int height, double fx_px, const PassiveStereoModel& m, std::mt19937& rng) {
  std::vector<float> out;
  PassiveStereoScratch scratch;
  passiveStereoDepth(z_m, rgb, width, height, fx_px, m, rng, &out, &scratch);
  return out;
}

void passiveStereoDepth(const std::vector<float>& z_m, const std::vector<uint8_t>& rgb, int width, int height,
                        double fx_px, const PassiveStereoModel& m, std::mt19937& rng, std::vector<float>* out,
                        PassiveStereoScratch* scratch) {
  const size_t n = static_cast<size_t>(width) * height;
  out->assign(n, kNan);
  if (z_m.size() != n || rgb.size() != 3 * n) return;
  const double fxb = fx_px * m.baseline_m;
  visibleInRight(z_m, width, height, fxb, &scratch->seen);
  textured(rgb, width, height, m, scratch);
  const char* seen = scratch->seen.data();
  const char* ok = scratch->ok.data();
  PixelNoise noise(rng);
  for (size_t i = 0; i < n; ++i) {
    if (!seen[i] || !ok[i]) continue;
    const double z = z_m[i];
    (*out)[i] = static_cast<float>(z + z * z * m.disparity_sigma_px / fxb * noise.normal(noise.next()));
  }
}

}  // namespace thorvald_sim
