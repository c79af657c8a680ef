// nextCanopyLayer: the layers of foliage in the arm's strip that the arm sweeps aside to look under them.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "cotton_harvester/control/canopy_search.h"

using cotton_harvester::control::CanopyLayer;
using cotton_harvester::control::CanopySearchParams;
using cotton_harvester::control::CloudView;
using cotton_harvester::control::nextCanopyLayer;

namespace {

/// A flat horizontal rectangle (a leaf seen from above) at depth z.
struct Patch {
  double x0, x1, y0, y1, z;
};

/// The organised cloud a pinhole camera looking down sees: each pixel's ray meets the shallowest patch it
/// crosses, or the ground at ground_z (NaN without ground).
struct PinholeCloud {
  int width, height;
  double fx, cx, cy;
  std::vector<float> xyz;
  PinholeCloud(int w, int h, double f, const std::vector<Patch>& patches, double ground_z)
      : width(w), height(h), fx(f), cx(0.5 * w), cy(0.5 * h), xyz(static_cast<std::size_t>(w) * h * 3) {
    for (int v = 0; v < h; ++v)
      for (int u = 0; u < w; ++u) {
        const double rx = (u - cx) / fx, ry = (v - cy) / fx;
        double z = ground_z;
        for (const Patch& p : patches) {
          const double x = rx * p.z, y = ry * p.z;
          if (p.z < z && x >= p.x0 && x <= p.x1 && y >= p.y0 && y <= p.y1) z = p.z;
        }
        float* q = &xyz[(static_cast<std::size_t>(v) * w + u) * 3];
        q[0] = static_cast<float>(rx * z), q[1] = static_cast<float>(ry * z), q[2] = static_cast<float>(z);
      }
  }
  CloudView view() const {
    CloudView c;
    c.data = reinterpret_cast<const std::uint8_t*>(xyz.data());
    c.rows = height;
    c.cols = width;
    c.point_step = 12;
    c.row_step = 12 * static_cast<std::size_t>(width);
    return c;
  }
};

constexpr double kFx = 700.0;
// The arm's reach across the row and its depths (top face of the housing) below the camera.
constexpr double kXLo = -0.6, kXHi = 0.2, kBelow = 1.30, kMaxDepth = 1.93;

}  // namespace

TEST(CanopySearch, GroundAndEmptyCloudsHoldNoLayer) {
  const CanopySearchParams p;
  const PinholeCloud ground(640, 360, kFx, {}, 2.2);  // the ground below the arm's lowest position
  EXPECT_FALSE(nextCanopyLayer(ground.view(), kFx, 0.0, kXLo, kXHi, kBelow, kMaxDepth, p));
  const PinholeCloud none(640, 360, kFx, {}, std::numeric_limits<double>::quiet_NaN());
  EXPECT_FALSE(nextCanopyLayer(none.view(), kFx, 0.0, kXLo, kXHi, kBelow, kMaxDepth, p));
  EXPECT_FALSE(nextCanopyLayer(CloudView{}, kFx, 0.0, kXLo, kXHi, kBelow, kMaxDepth, p));
  EXPECT_FALSE(nextCanopyLayer(ground.view(), std::nan(""), 0.0, kXLo, kXHi, kBelow, kMaxDepth, p));
}

TEST(CanopySearch, FindsTheTopLeafInTheStripAndItsSpan) {
  const CanopySearchParams p;
  // A 12 x 10 cm leaf 1.55 m below the camera in the arm's strip, a deeper one under it.
  const PinholeCloud cloud(1280, 720, kFx, {{-0.26, -0.14, -0.05, 0.05, 1.55}, {-0.3, -0.05, -0.06, 0.06, 1.72}}, 2.2);
  const auto layer = nextCanopyLayer(cloud.view(), kFx, 0.0, kXLo, kXHi, kBelow, kMaxDepth, p);
  ASSERT_TRUE(layer);
  EXPECT_NEAR(layer->top_m, 1.55, 1e-3);
  EXPECT_NEAR(layer->sweep_depth_m, 1.55 - p.above_layer_m, 1e-3);
  EXPECT_NEAR(layer->x_min_m, -0.26, 0.01);
  EXPECT_NEAR(layer->x_max_m, -0.14, 0.01);
  // The deeper leaf is the next layer once the sweep passed the first.
  const auto next = nextCanopyLayer(cloud.view(), kFx, 0.0, kXLo, kXHi, 1.55 + 0.08, kMaxDepth, p);
  ASSERT_TRUE(next);
  EXPECT_NEAR(next->top_m, 1.72, 1e-3);
  EXPECT_NEAR(next->x_min_m, -0.3, 0.01);
  EXPECT_NEAR(next->x_max_m, -0.05, 0.01);
  EXPECT_FALSE(nextCanopyLayer(cloud.view(), kFx, 0.0, kXLo, kXHi, 1.72 + 0.08, kMaxDepth, p));
}

TEST(CanopySearch, IgnoresWhatLiesOutsideTheStripTheReachOrTheDepths) {
  const CanopySearchParams p;  // strip +-8 cm along the row
  // Beside the strip along the row, beyond the arm's reach across it, above the housing's rest, below its lowest.
  const PinholeCloud cloud(1280, 720, kFx,
                           {{-0.3, -0.15, 0.2, 0.3, 1.5},
                            {0.35, 0.5, -0.05, 0.05, 1.5},
                            {-0.3, -0.15, -0.05, 0.05, 1.2},
                            {-0.45, -0.35, -0.05, 0.05, 1.98}},
                           2.2);
  EXPECT_FALSE(nextCanopyLayer(cloud.view(), kFx, 0.0, kXLo, kXHi, kBelow, kMaxDepth, p));
  // The first one is in the strip of an arm 0.25 m further along the row.
  const auto shifted = nextCanopyLayer(cloud.view(), kFx, 0.25, kXLo, kXHi, kBelow, kMaxDepth, p);
  ASSERT_TRUE(shifted);
  EXPECT_NEAR(shifted->top_m, 1.5, 1e-3);
}

TEST(CanopySearch, ALayerMustCoverHalfABollsDiscAtAnyResolution) {
  const CanopySearchParams p;  // half the disc of a 3.5 cm boll
  // A stem's top (1.6 cm square) and a twig are not worth a sweep; a leaf is, in a full or a quarter-size image.
  const std::vector<Patch> small{{-0.208, -0.192, -0.008, 0.008, 1.45}, {-0.1, -0.05, -0.004, 0.004, 1.5}};
  for (const double scale : {1.0, 0.5}) {
    const double fx = kFx * scale;
    const PinholeCloud twigs(static_cast<int>(1280 * scale), static_cast<int>(720 * scale), fx, small, 2.2);
    EXPECT_FALSE(nextCanopyLayer(twigs.view(), fx, 0.0, kXLo, kXHi, kBelow, kMaxDepth, p)) << scale;
    std::vector<Patch> with_leaf = small;
    with_leaf.push_back({-0.05, 0.0, -0.025, 0.025, 1.6});  // 5 x 5 cm: 0.65 of a 3.5 cm boll's disc
    const PinholeCloud leaf(static_cast<int>(1280 * scale), static_cast<int>(720 * scale), fx, with_leaf, 2.2);
    const auto layer = nextCanopyLayer(leaf.view(), fx, 0.0, kXLo, kXHi, kBelow, kMaxDepth, p);
    ASSERT_TRUE(layer) << scale;
    EXPECT_NEAR(layer->top_m, 1.6, 1e-3) << scale;
  }
}

TEST(CanopySearch, PlansEachLayersSweepFromTheTop) {
  const CanopySearchParams p;  // housing 8 cm tall, half side 5 cm; 1 cm above the layer, 15 cm past it
  cotton_harvester::control::ArmWorkspace arm;  // extension 0 at x = -0.55, travel 0.70, rest 1.20, lowest 1.93
  const PinholeCloud cloud(
      1280, 720, kFx,
      {{-0.26, -0.14, -0.05, 0.05, 1.55}, {-0.3, -0.05, -0.06, 0.06, 1.72}, {0.3, 0.45, -0.05, 0.05, 1.8}}, 2.2);
  cotton_harvester::control::CanopySearch search(arm, p);
  const auto first = search.next(cloud.view(), kFx);
  ASSERT_TRUE(first);
  EXPECT_NEAR(first->depth_m, 1.54, 1e-3);
  EXPECT_NEAR(first->from_extension_m, -0.26 + 0.55 - 0.05 - 0.02, 0.01);
  EXPECT_NEAR(first->to_extension_m, -0.14 + 0.55 + 0.05 + 0.15, 0.01);
  const auto second = search.next(cloud.view(), kFx);  // below what the first sweep passed through
  ASSERT_TRUE(second);
  EXPECT_NEAR(second->depth_m, 1.71, 1e-3);
  EXPECT_NEAR(second->to_extension_m, -0.05 + 0.55 + 0.05 + 0.15, 0.01);  // at the end of the travel
  EXPECT_LE(second->to_extension_m, 0.70);
  // The third leaf lies beyond the housing's reach: no layer is left.
  EXPECT_FALSE(search.next(cloud.view(), kFx));
}

TEST(CanopySearch, FocalLengthFromTheCloud) {
  const PinholeCloud cloud(640, 360, 350.0, {{-0.2, 0.0, -0.1, 0.1, 1.5}}, 2.2);
  EXPECT_NEAR(cotton_harvester::control::focalFromCloud(cloud.view()), 350.0, 1.0);
  const PinholeCloud none(640, 360, 350.0, {}, std::numeric_limits<double>::quiet_NaN());
  EXPECT_EQ(cotton_harvester::control::focalFromCloud(none.view()), 0.0);
  EXPECT_EQ(cotton_harvester::control::focalFromCloud(CloudView{}), 0.0);
}

TEST(CanopySearch, ParamsAreChecked) {
  CanopySearchParams p;
  EXPECT_EQ(p.check(), "");
  p.max_passes = 0;
  EXPECT_NE(p.check(), "");
  p = CanopySearchParams();
  p.min_cover_fraction = 1.5;
  EXPECT_NE(p.check(), "");
  p = CanopySearchParams();
  p.strip_half_m = std::nan("");
  EXPECT_NE(p.check(), "");
}
