// shadeDaylight against its formula on synthetic views: the texture is valueNoise of the world point (also far from
// the world's origin), Lambert's cosine comes from the depth image's neighbours, a pixel in the shadow map's shade
// gets only the ambient light, and pixels that see nothing keep their colour.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "thorvald_sim/daylight.h"

namespace ts = thorvald_sim;

namespace {

constexpr int kW = 160, kH = 120;
const ts::Intrinsics kK{150.0, 150.0, 79.5, 59.5};

/// A camera at `origin` looking straight down (x right = world x, y down = world -y) at a flat ground `height_m`
/// below it: geom 0 everywhere but the top rows (nothing seen).
struct GroundView {
  ts::SensorPose pose;
  ts::RenderedView view;
  GroundView(const Eigen::Vector3d& origin, double height_m, int sky_rows) {
    pose.origin = origin;
    pose.rotation << 1, 0, 0, 0, -1, 0, 0, 0, -1;
    view.width = kW, view.height = kH;
    view.depth_m.assign(kW * kH, static_cast<float>(height_m));
    view.geom.assign(kW * kH, 0);
    for (int i = 0; i < sky_rows * kW; ++i) view.depth_m[i] = std::numeric_limits<float>::infinity(), view.geom[i] = -1;
  }
  Eigen::Vector3d world(int u, int v) const {
    const double z = view.depth_m[v * kW + u];
    return pose.origin + pose.rotation * Eigen::Vector3d(z * (u - kK.cx) / kK.fx, z * (v - kK.cy) / kK.fy, z);
  }
};

ts::ColorImage grey(int level) {
  ts::ColorImage rgb;
  rgb.width = kW, rgb.height = kH;
  rgb.rgb.assign(3 * kW * kH, static_cast<uint8_t>(level));
  return rgb;
}

}  // namespace

TEST(Daylight, TextureIsValueNoiseOfTheWorldPointEvenFarFromTheOrigin) {
  for (const Eigen::Vector3d& origin : {Eigen::Vector3d(0.3, -0.2, 2.2), Eigen::Vector3d(1234.567, -876.5, 2.2)}) {
    const GroundView g(origin, 2.2, 10);
    ts::Daylight light = ts::overcastDaylight(0.9, 0.6);
    light.direct = 0.0;  // the gain is the texture times ambient times exposure
    light.exposure = 1.05;
    ts::ColorImage rgb = grey(150);
    ts::shadeDaylight(g.view, g.pose, kK, light, nullptr, {0.35f}, &rgb);
    int off = 0, sky_changed = 0;
    double spread = 0.0;
    for (int v = 0; v < kH; ++v)
      for (int u = 0; u < kW; ++u) {
        const int got = rgb.rgb[3 * (v * kW + u)];
        if (v < 10) {
          sky_changed += got != 150;
          continue;
        }
        const Eigen::Vector3d p = g.world(u, v);
        const double noise = 0.6 * ts::valueNoise(p, 0.004) + 0.4 * ts::valueNoise(p, 0.02);
        const double want = 150.0 * (1.0 + 0.35 * noise) * light.ambient * light.exposure;
        off += std::fabs(got - want) > 0.51;  // rounding, and a float's rounding where want is near a half
        spread += std::fabs(noise);
      }
    EXPECT_EQ(sky_changed, 0);
    EXPECT_LE(off, kW * kH / 1000) << "origin " << origin.transpose();
    EXPECT_GT(spread / (kW * (kH - 10)), 0.1);  // there is a texture to compare
  }
}

TEST(Daylight, LambertFromTheDepthNeighboursAndTheShadowMapsShade) {
  // A ground tilted by 0.3 rad about the camera's x axis: depth grows down the image. No texture.
  GroundView g(Eigen::Vector3d(0.0, 0.0, 2.0), 2.0, 0);
  const double tilt = 0.3;
  for (int v = 0; v < kH; ++v) {
    const double y = (v - kK.cy) / kK.fy;  // the plane z = 2 + tan(tilt) y z  ->  z = 2 / (1 - tan(tilt) y)
    for (int u = 0; u < kW; ++u) g.view.depth_m[v * kW + u] = static_cast<float>(2.0 / (1.0 - std::tan(tilt) * y));
  }
  const ts::Daylight sun = ts::sunnyDaylight(0.9, 0.6);
  // The plane Z - tan(tilt) Y = 2 of the optical frame: its normal facing the camera is (0, tan(tilt), -1) normalised.
  const Eigen::Vector3d n_cam = Eigen::Vector3d(0.0, std::tan(tilt), -1.0).normalized();
  const double cosine = std::max(0.0, n_cam.dot(g.pose.rotation.transpose() * sun.toSun()));
  ASSERT_GT(cosine, 0.3);
  ts::ColorImage rgb = grey(100);
  ts::shadeDaylight(g.view, g.pose, kK, sun, nullptr, {0.0f}, &rgb);
  const int lit = static_cast<int>(std::lround(100.0 * (sun.ambient + sun.direct * cosine) * sun.exposure));
  int off = 0;
  for (int v = 0; v < kH; ++v)
    for (int u = 0; u < kW; ++u) off += std::abs(rgb.rgb[3 * (v * kW + u) + 1] - lit) > 1;
  EXPECT_EQ(off, 0) << "want " << lit;

  // A shadow map from the sun that sees something 1 m nearer the sun than every surface point: all in shade.
  ts::ShadowMap shade;
  shade.valid = true;
  const Eigen::Vector3d z = -sun.toSun(), x = z.cross(Eigen::Vector3d::UnitZ()).normalized();
  shade.pose.origin = Eigen::Vector3d(0, 0, 0) + 20.0 * sun.toSun();
  shade.pose.rotation.col(0) = x, shade.pose.rotation.col(1) = z.cross(x), shade.pose.rotation.col(2) = z;
  shade.view.width = shade.view.height = 400;
  shade.view.k = ts::Intrinsics{2000.0, 2000.0, 199.5, 199.5};  // 4 m across at 20 m
  shade.depth.width = shade.depth.height = 400;
  shade.depth.depth_m.assign(400 * 400, 18.0f);
  shade.depth.geom.assign(400 * 400, 0);
  rgb = grey(100);
  ts::shadeDaylight(g.view, g.pose, kK, sun, &shade, {0.0f}, &rgb);
  const int dark = static_cast<int>(std::lround(100.0 * sun.ambient * sun.exposure));
  off = 0;
  for (int v = 0; v < kH; ++v)
    for (int u = 0; u < kW; ++u) off += std::abs(rgb.rgb[3 * (v * kW + u)] - dark) > 1;
  EXPECT_EQ(off, 0) << "want " << dark;
}
