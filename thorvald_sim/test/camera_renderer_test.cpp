// The rasterised cameras against the ray caster and the worlds' known geometry.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "test_scene.h"
#include "thorvald_sim/camera_renderer.h"
#include "thorvald_sim/geom_writer.h"
#include "thorvald_sim/sensors.h"
#include "thorvald_sim/world.h"

namespace ts = thorvald_sim;
using ts::test::optical;
using ts::test::StaticWorld;

namespace {

ts::CameraView viewOf(const ts::DepthCameraSpec& s) {
  ts::CameraView v;
  v = ts::cameraView(s, true, 60.0);
  v.near_m = 0.05;
  return v;
}

// Depth along the optical axis seen by the ray caster at pixel (u, v), -1 for nothing; `geom` gets its id.
double castPixel(const ts::RayCaster& caster, const ts::SensorPose& cam, const ts::Intrinsics& k, int u, int v,
                 int* geom) {
  const Eigen::Vector3d ray((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
  const double d = caster.cast(cam.origin, cam.rotation * ray.normalized(), geom);
  return d < 0 ? -1.0 : d / ray.norm();
}

/// How a rendered view agrees with the ray caster pixel by pixel: pixels that see the same geom (or none), the
/// largest depth difference among those, and the geom of every agreeing pixel that sees one.
struct Agreement {
  int total = 0, same = 0;
  double worst_depth_m = 0.0;
  std::vector<int> agreeing_geoms;
};

Agreement compareWithRayCaster(ts::RayCaster& caster, const ts::SensorPose& cam, const ts::DepthCameraSpec& spec,
                               const ts::RenderedView& view) {
  caster.prepare(cam.origin, 1e3, cam.rotation.col(2), M_PI);
  const auto k = ts::intrinsics(spec);
  Agreement a;
  for (int v = 0; v < spec.height; ++v)
    for (int u = 0; u < spec.width; ++u) {
      int g = -1;
      const double z = castPixel(caster, cam, k, u, v, &g);
      const size_t i = static_cast<size_t>(v) * spec.width + u;
      ++a.total;
      if (view.geom[i] != g) continue;
      ++a.same;
      if (g < 0) continue;
      a.worst_depth_m = std::max(a.worst_depth_m, std::fabs(view.depth_m[i] - z));
      a.agreeing_geoms.push_back(g);
    }
  return a;
}

struct PrimitiveCase {
  const char* name;
  const char* geom;  // geom name in the world
  Eigen::Vector3d eye, forward, down;
};

// One primitive large enough to fill the whole image, on nothing else.
ts::WorldDescription primitiveWorld(const std::string& which) {
  ts::GeomWriter w;
  const char* rgba = "0.8 0.4 0.2 1";  // exact in 8 bits: 204 102 51
  if (which == "plane") w.plane("shape", {0, 0, 0}, 50.0, rgba);
  if (which == "box") w.box("shape", {0, 0, -1.0}, {4.0, 3.0, 1.0}, rgba);
  if (which == "sphere") w.sphere("shape", {0, 0, -20.0}, 20.0, rgba);
  if (which == "capsule") w.capsule("shape", {-6.0, 0, -4.0}, {6.0, 0, -4.0}, 4.0, rgba);
  if (which == "cylinder") w.cylinder("shape", {0, 0, -4.0}, 4.0, 4.0, rgba);
  if (which == "ellipsoid") w.ellipsoid("shape", {0, 0, -3.0}, {6.0, 5.0, 3.0}, 0.4, rgba);
  return {which, w.str(), 0.0};
}

}  // namespace

// Every primitive type, seen from about 1 m with its surface filling the image: the rendered depth and geom at the
// four corners and the centre are the ray caster's (MuJoCo's analytic ray-geom intersections), and so is the colour.
TEST(CameraRenderer, EveryPrimitiveMatchesTheRayCasterAtCornersAndCentre) {
  for (const char* shape : {"plane", "box", "sphere", "capsule", "cylinder", "ellipsoid"}) {
    SCOPED_TRACE(shape);
    StaticWorld w(primitiveWorld(shape));
    ts::CameraRenderer renderer(w.model.get());
    ts::RayCaster caster(w.model.get(), w.data.get(), -1);
    caster.prepare(Eigen::Vector3d::Zero(), 1e3, Eigen::Vector3d::UnitZ(), M_PI);
    ts::DepthCameraSpec spec;
    spec.width = 320, spec.height = 240, spec.hfov_rad = 1.2;
    spec.range_min_m = 0.1, spec.range_max_m = 20.0;
    spec.noise_coeff = 0.0, spec.dropout = 0.0, spec.grazing_limit_rad = M_PI;
    // Looking down, tilted forward by 0.3 rad, so depth varies across the image.
    const auto cam = optical({0.2, 0.1, 1.0}, {0.3, 0.1, -1.0}, {1, 0, 0});
    ts::RenderedView view;
    renderer.render(w.data.get(), cam, viewOf(spec), -1, &view);
    std::mt19937 rng(1);
    const ts::DepthImage img = ts::depthFromView(view, caster, cam, spec, rng);
    ts::ColorCameraSpec cs;
    cs.width = spec.width, cs.height = spec.height, cs.hfov_rad = spec.hfov_rad;
    const ts::ColorImage colour = ts::colorFromView(view, w.model.get(), cs);
    const int shape_id = mj_name2id(w.model.get(), mjOBJ_GEOM, "shape");
    ASSERT_GE(shape_id, 0);
    const auto k = ts::intrinsics(spec);
    const int cu = spec.width / 2, cv = spec.height / 2;
    for (auto uv : {std::pair<int, int>{0, 0},
                    {spec.width - 1, 0},
                    {0, spec.height - 1},
                    {spec.width - 1, spec.height - 1},
                    {cu, cv}}) {
      SCOPED_TRACE(::testing::Message() << "pixel " << uv.first << " " << uv.second);
      int g = -1;
      const double z = castPixel(caster, cam, k, uv.first, uv.second, &g);
      ASSERT_EQ(g, shape_id);
      const size_t i = static_cast<size_t>(uv.second) * spec.width + uv.first;
      EXPECT_EQ(view.geom[i], shape_id);
      // Flat faces come from the 24-bit z-buffer (near 0.05 m): z^2 / (near 2^24) is below 2e-5 m here.
      EXPECT_NEAR(view.depth_m[i], z, 5e-5);
      EXPECT_NEAR(img.points[i].z(), z, 5e-5);
      EXPECT_NEAR(img.points[i].x(), (uv.first - k.cx) / k.fx * z, 5e-5);
      EXPECT_NEAR(img.points[i].y(), (uv.second - k.cy) / k.fy * z, 5e-5);
      EXPECT_EQ(colour.rgb[3 * i + 0], 204);
      EXPECT_EQ(colour.rgb[3 * i + 1], 102);
      EXPECT_EQ(colour.rgb[3 * i + 2], 51);
    }
  }
}

// A whole image of the cotton row (pots, stems, leaves, bolls, slope): nearly every pixel sees the same geom as
// the ray caster, and where it does the depth agrees; only silhouettes of the tessellated curved geoms differ.
TEST(CameraRenderer, CottonRowImageAgreesWithTheRayCaster) {
  ts::CottonRowParams p;
  p.slope_deg = 2.77;
  ts::CottonRowTruth t;
  StaticWorld w(ts::makeCottonRowWorld(p, &t));
  ts::CameraRenderer renderer(w.model.get());
  ts::RayCaster caster(w.model.get(), w.data.get(), -1);
  ts::DepthCameraSpec spec;
  spec.width = 320, spec.height = 180, spec.range_max_m = 20.0;
  // The cotton paper's calibrated ZED intrinsics at a quarter of 1280x720: principal point off the centre.
  spec.focal_px = 699.936 / 4, spec.cx_px = 685.286 / 4, spec.cy_px = 361.248 / 4;
  const auto cam = optical(t.plant_bases[4] + Eigen::Vector3d(-0.6, 0.3, 2.2), {0.3, -0.1, -1.0}, {1, 0, 0});
  ts::RenderedView view;
  renderer.render(w.data.get(), cam, viewOf(spec), -1, &view);
  const Agreement a = compareWithRayCaster(caster, cam, spec, view);
  int bolls = 0;
  for (int g : a.agreeing_geoms) {
    const char* name = mj_id2name(w.model.get(), mjOBJ_GEOM, g);
    if (name && std::string(name).find("boll") != std::string::npos) ++bolls;
  }
  EXPECT_GT(a.same, 0.995 * a.total);
  EXPECT_LT(a.worst_depth_m, 1e-4);
  EXPECT_GT(bolls, 50);  // the bolls are in view and agree
}

TEST(CameraRenderer, LeavesOutOnlyGeomsOutOfView) {
  // The greenhouse seen from the headland at an angle: the geoms outside the view are not drawn,
  // and the image still agrees with the ray caster pixel by pixel.
  StaticWorld w(ts::makeGreenhouseWorld(ts::GreenhouseParams(), nullptr));
  ts::CameraRenderer renderer(w.model.get());
  ts::RayCaster caster(w.model.get(), w.data.get(), -1);
  ts::DepthCameraSpec spec;
  spec.width = 160, spec.height = 120;
  const auto cam = optical({-1.2, 1.6, 0.8}, {1.0, 0.3, -0.6}, {0, 0, -1});
  ts::RenderedView view;
  renderer.render(w.data.get(), cam, viewOf(spec), -1, &view);
  EXPECT_GT(renderer.culledGeoms(), w.model->ngeom / 5);  // about a quarter of the geoms lie behind or beside it
  const Agreement a = compareWithRayCaster(caster, cam, spec, view);
  EXPECT_GT(a.agreeing_geoms.size(), a.total / 2u);
  EXPECT_GT(a.same, 0.995 * a.total);
}

// The existing ray-cast depth test, rendered: points on the pipes lie on their surfaces within 0.1 mm.
TEST(CameraRenderer, PipePointsLieOnThePipes) {
  ts::GreenhouseTruth t;
  StaticWorld w(ts::makeGreenhouseWorld(ts::GreenhouseParams(), &t));
  ts::CameraRenderer renderer(w.model.get());
  ts::RayCaster caster(w.model.get(), w.data.get(), -1);
  ts::DepthCameraSpec spec;
  spec.width = 160;
  spec.height = 120;
  spec.noise_coeff = 0.0;
  spec.dropout = 0.0;
  std::mt19937 rng(1);
  const auto& set = t.rail_sets[2];
  const auto cam = optical({-1.2, set.start_y, 0.8}, {1.0, 0.0, -0.6}, {0, 0, -1});
  ts::RenderedView view;
  renderer.render(w.data.get(), cam, viewOf(spec), -1, &view);
  const auto img = ts::depthFromView(view, caster, cam, spec, rng);
  ASSERT_EQ(img.points.size(), 160u * 120u);
  int on_pipe = 0, valid = 0;
  const double r = 0.5 * t.params.pipe_diameter_m;
  for (const auto& p : img.points) {
    if (!std::isfinite(p.z())) continue;
    ++valid;
    const Eigen::Vector3d wp = cam.origin + cam.rotation * p.cast<double>();
    if (wp.z() < t.floor_z + 0.01 || wp.x() < set.start_x || wp.x() > 6.0) continue;
    if (std::fabs(wp.y() - set.start_y) > 0.5) continue;
    ++on_pipe;
    const double dy = std::min(std::fabs(wp.y() - set.pipe_y[0]), std::fabs(wp.y() - set.pipe_y[1]));
    const double dx = std::max(0.0, set.start_x + r - wp.x());
    EXPECT_NEAR(std::sqrt(dx * dx + dy * dy + std::pow(wp.z() - t.pipe_centre_z, 2)), r, 1e-4) << wp.transpose();
  }
  EXPECT_GT(valid, 160 * 120 / 2);
  EXPECT_GT(on_pipe, 20);
}

TEST(CameraRenderer, NoiseGrowsWithDepthAndDropoutsHappen) {
  StaticWorld w(ts::makeFlatWorld());
  ts::CameraRenderer renderer(w.model.get());
  ts::RayCaster caster(w.model.get(), w.data.get(), -1);
  ts::DepthCameraSpec spec;
  spec.width = 64;
  spec.height = 48;
  spec.noise_coeff = 0.005;
  spec.dropout = 0.1;
  std::mt19937 rng(3);
  const auto cam = optical({0, 0, 2.0}, {0, 0, -1}, {1, 0, 0});
  ts::RenderedView view;
  renderer.render(w.data.get(), cam, viewOf(spec), -1, &view);
  const auto img = ts::depthFromView(view, caster, cam, spec, rng);
  double sum = 0, sq = 0;
  int n = 0;
  for (const auto& p : img.points)
    if (std::isfinite(p.z())) sum += p.z() - 2.0, sq += (p.z() - 2.0) * (p.z() - 2.0), ++n;
  const double mean = sum / n, sd = std::sqrt(sq / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 0.003);
  EXPECT_NEAR(sd, 0.02, 0.003);
  EXPECT_NEAR(1.0 - n / (64.0 * 48.0), 0.1, 0.03);
}

TEST(CameraRenderer, DepthNoiseIsNormal) {
  // Many pixels on a plane 2 m away: the noise has the configured spread and a normal distribution's tails.
  StaticWorld w(ts::makeFlatWorld());
  ts::CameraRenderer renderer(w.model.get());
  ts::RayCaster caster(w.model.get(), w.data.get(), -1);
  ts::DepthCameraSpec spec;
  spec.width = 320;
  spec.height = 240;
  spec.noise_coeff = 0.005;  // sigma = 0.005 * 2^2 = 0.02 m
  spec.dropout = 0.0;
  std::mt19937 rng(11);
  const auto cam = optical({0, 0, 2.0}, {0, 0, -1}, {1, 0, 0});
  ts::RenderedView view;
  renderer.render(w.data.get(), cam, viewOf(spec), -1, &view);
  const auto img = ts::depthFromView(view, caster, cam, spec, rng);
  std::vector<double> e;
  for (const auto& p : img.points)
    if (std::isfinite(p.z())) e.push_back((p.z() - 2.0) / 0.02);
  ASSERT_GT(e.size(), 70000u);
  double sum = 0, sq = 0;
  int beyond2 = 0, beyond3 = 0;
  for (double x : e) {
    sum += x, sq += x * x;
    beyond2 += std::fabs(x) > 2.0;
    beyond3 += std::fabs(x) > 3.0;
  }
  const double n = static_cast<double>(e.size()), mean = sum / n, sd = std::sqrt(sq / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 0.02);
  EXPECT_NEAR(sd, 1.0, 0.015);
  EXPECT_NEAR(beyond2 / n, 0.0455, 0.004);   // P(|x| > 2) of a normal
  EXPECT_NEAR(beyond3 / n, 0.0027, 0.0012);  // P(|x| > 3)
}

TEST(CameraRenderer, NoDepthWhereTheSurfaceIsSeenMoreObliquelyThanTheGrazingLimit) {
  // A plane and a box's top face (both at z = 0) seen from 1 m up, looking ahead and down: a pixel has depth exactly
  // where its ray meets the surface at an incidence within the limit (cos = |ray_z| >= cos(70 deg)).
  for (const char* shape : {"plane", "box"}) {
    SCOPED_TRACE(shape);
    StaticWorld w(primitiveWorld(shape));
    ts::CameraRenderer renderer(w.model.get());
    ts::RayCaster caster(w.model.get(), w.data.get(), -1);
    ts::DepthCameraSpec spec;
    spec.width = 160, spec.height = 120, spec.range_max_m = 30.0;
    spec.noise_coeff = 0.0, spec.dropout = 0.0, spec.grazing_limit_rad = 70.0 * M_PI / 180.0;
    const auto cam = optical({0, 0, 1.0}, {1.0, 0.0, -0.45}, {0, 0, -1});
    ts::RenderedView view;
    renderer.render(w.data.get(), cam, viewOf(spec), -1, &view);
    std::mt19937 rng(1);
    const auto img = ts::depthFromView(view, caster, cam, spec, rng);
    const auto k = ts::intrinsics(spec);
    const double min_cos = std::cos(spec.grazing_limit_rad);
    int checked = 0, valid = 0, refused = 0;
    for (int v = 0; v < spec.height; ++v)
      for (int u = 0; u < spec.width; ++u) {
        const Eigen::Vector3d dir =
            cam.rotation * Eigen::Vector3d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0).normalized();
        if (dir.z() > -1e-6) continue;  // above the horizon
        const Eigen::Vector3d hit = cam.origin + dir * (-cam.origin.z() / dir.z());
        if (std::string(shape) == "box" && (std::fabs(hit.x()) > 3.9 || std::fabs(hit.y()) > 2.9)) continue;
        if ((hit - cam.origin).norm() > 25.0 || std::fabs(-dir.z() - min_cos) < 1e-3) continue;
        const bool expect_depth = -dir.z() >= min_cos;
        const bool has_depth = std::isfinite(img.points[static_cast<size_t>(v) * spec.width + u].z());
        EXPECT_EQ(has_depth, expect_depth) << "pixel " << u << "," << v << " cos " << -dir.z();
        ++checked;
        valid += expect_depth;
        refused += !expect_depth;
      }
    EXPECT_GT(valid, 1000);  // both outcomes occur in the image
    EXPECT_GT(refused, 300);
    EXPECT_GT(checked, 5000);
  }
}

TEST(CameraRenderer, RenderAndDepthImageDoNotDependOnTheThreads) {
  StaticWorld w(ts::makeGreenhouseWorld(ts::GreenhouseParams(), nullptr));
  ts::CameraRenderer renderer(w.model.get());
  ts::RayCaster caster(w.model.get(), w.data.get(), -1);
  ts::DepthCameraSpec spec;
  spec.width = 160, spec.height = 120;
  const auto cam = optical({-1.2, 1.6, 0.8}, {1.0, 0.0, -0.6}, {0, 0, -1});
  ts::RenderedView view, view3;
  renderer.render(w.data.get(), cam, viewOf(spec), -1, &view);
  // The render's own read-back on 3 threads gives the same view, pipes (curved, refined per pixel) included.
  renderer.render(w.data.get(), cam, viewOf(spec), -1, &view3, 3);
  EXPECT_EQ(view.geom, view3.geom);
  EXPECT_EQ(view.depth_m, view3.depth_m);
  int pipe_pixels = 0;
  for (int g : view.geom) pipe_pixels += g >= 0 && w.model->geom_type[g] == mjGEOM_CAPSULE;
  EXPECT_GT(pipe_pixels, 50);
  ts::DepthImage one, three;
  std::mt19937 rng1(5), rng3(5);
  ts::depthFromView(view, caster, cam, spec, rng1, &one, 1);
  ts::depthFromView(view, caster, cam, spec, rng3, &three, 3);
  int valid = 0;
  for (size_t i = 0; i < one.points.size(); ++i) {
    if (!std::isfinite(one.points[i].z())) {
      EXPECT_FALSE(std::isfinite(three.points[i].z()));
      continue;
    }
    ++valid;
    EXPECT_EQ(one.points[i], three.points[i]);
  }
  EXPECT_GT(valid, 160 * 120 / 2);
  EXPECT_EQ(rng1(), rng3());  // the caller's engine advanced the same
}

TEST(CameraRenderer, BollPixelIsWhiteAndSkyIsBackground) {
  ts::CottonRowTruth t;
  StaticWorld w(ts::makeCottonRowWorld(ts::CottonRowParams(), &t));
  ts::CameraRenderer renderer(w.model.get());
  ts::ColorCameraSpec spec;
  spec.width = 64;
  spec.height = 48;
  int best = -1;
  for (size_t i = 0; i < t.bolls.size(); ++i)
    if (t.boll_plant[i] == 3 && (best < 0 || t.bolls[i].z() > t.bolls[best].z())) best = static_cast<int>(i);
  ASSERT_GE(best, 0);
  const auto cam = optical(t.bolls[best] + Eigen::Vector3d(0, 0, 0.5), {0, 0, -1}, {1, 0, 0});
  ts::CameraView cv;
  cv.width = 64, cv.height = 48, cv.k = ts::intrinsics(spec);
  ts::RenderedView view;
  renderer.render(w.data.get(), cam, cv, -1, &view);
  const auto img = ts::colorFromView(view, w.model.get(), spec);
  const int u = 32, v = 24;  // the centre pixel's ray passes within 0.6 mm of the boll's centre
  const uint8_t* px = &img.rgb[(v * 64 + u) * 3];
  EXPECT_EQ(px[0], 255);
  EXPECT_EQ(px[1], 255);
  EXPECT_EQ(px[2], 255);
  // Looking up: nothing but the background.
  renderer.render(w.data.get(), optical({0, 0, 1.0}, {0, 0, 1}, {1, 0, 0}), cv, -1, &view);
  const auto sky = ts::colorFromView(view, w.model.get(), spec);
  for (int c = 0; c < 3; ++c) EXPECT_EQ(sky.rgb[c], spec.background[c]);
  EXPECT_EQ(view.geom[0], -1);
  EXPECT_TRUE(std::isinf(view.depth_m[0]));
}

TEST(CameraRenderer, DoesNotSeeItsOwnRobotButSeesOthers) {
  ts::test::TestScene s(ts::makeFlatWorld(), {ts::test::fourWheelSteered(), ts::test::fourWheelSteered()},
                        {{{0, 0, 0}}, {{3.0, 0, 0}}});
  s.drive(0, 0, 0, 0, 0.5);
  ts::CameraRenderer renderer(s.sim->model());
  ts::RayCaster own(s.sim->model(), s.sim->data(), s.sim->robot(0).root_body);
  own.prepare(Eigen::Vector3d::Zero(), 1e3, Eigen::Vector3d::UnitX(), M_PI);
  // Inside robot 0's frame box at its height, looking forward along x at robot 1.
  const auto cam = optical({0, 0, 0.55}, {1, 0, 0}, {0, 0, -1});
  ts::CameraView cv;
  cv.width = 32, cv.height = 24, cv.k = ts::intrinsics(32, 24, 1.2);
  ts::RenderedView view;
  renderer.render(s.sim->data(), cam, cv, s.sim->robot(0).root_body, &view);
  const auto& k = cv.k;
  int g = -1;
  const double z = castPixel(own, cam, k, 16, 12, &g);
  ASSERT_GE(g, 0);
  EXPECT_EQ(s.sim->model()->body_rootid[s.sim->model()->geom_bodyid[g]], s.sim->robot(1).root_body);
  EXPECT_EQ(view.geom[12 * 32 + 16], g);
  EXPECT_NEAR(view.depth_m[12 * 32 + 16], z, 1e-4);
  EXPECT_NEAR(z, 3.0 - 0.675, 0.02);
  EXPECT_EQ(renderer.frames(), 1u);
}

TEST(CameraRenderer, RefusesImagesLargerThanTheModelAllows) {
  StaticWorld w(ts::makeFlatWorld());
  ts::CameraRenderer renderer(w.model.get());
  ts::CameraView cv;
  cv.width = renderer.maxWidth() + 1;
  ts::RenderedView view;
  EXPECT_THROW(renderer.render(w.data.get(), optical({0, 0, 1}, {0, 0, -1}, {1, 0, 0}), cv, -1, &view),
               ts::RenderError);
  cv.width = 64, cv.near_m = 0.0;
  EXPECT_THROW(renderer.render(w.data.get(), optical({0, 0, 1}, {0, 0, -1}, {1, 0, 0}), cv, -1, &view),
               ts::RenderError);
  EXPECT_EQ(renderer.frames(), 0u);
}

// The z-buffer ends at the far plane (1.001 range_max for a depth camera): a wall seen at an angle, from 4 m to
// beyond 8 m along the optical axis, has the ray caster's depth (within 0.1 mm, where the 24-bit z-buffer is coarsest)
// up to range_max, no depth beyond it, and no geom at all beyond the far plane.
TEST(CameraRenderer, DepthIsExactUpToTheFarPlaneAndNoneBeyond) {
  ts::GeomWriter gw;
  gw.box("wall", {4.9, 0.0, 0.0}, {0.1, 30.0, 8.0}, "0.8 0.4 0.2 1");
  StaticWorld w(ts::WorldDescription{"wall", gw.str(), 0.0});
  ts::CameraRenderer renderer(w.model.get());
  ts::RayCaster caster(w.model.get(), w.data.get(), -1);
  ts::DepthCameraSpec spec;
  spec.width = 160, spec.height = 120, spec.hfov_rad = 1.2;
  spec.range_min_m = 0.3, spec.range_max_m = 6.0, spec.noise_coeff = 0.0, spec.dropout = 0.0;
  const ts::CameraView cv = ts::cameraView(spec, false);
  ASSERT_NEAR(cv.far_m, 6.006, 1e-9);
  const auto cam = optical({0, 0, 0}, {std::cos(0.5), std::sin(0.5), 0.0}, {0, 0, -1});
  ts::RenderedView view;
  renderer.render(w.data.get(), cam, cv, -1, &view);
  std::mt19937 rng(3);
  const ts::DepthImage img = ts::depthFromView(view, caster, cam, spec, rng);
  caster.prepare(cam.origin, 1e3, cam.rotation.col(2), M_PI);
  const auto k = ts::intrinsics(spec);
  const int wall = mj_name2id(w.model.get(), mjOBJ_GEOM, "wall");
  int near_pixels = 0, far_pixels = 0;
  for (int v = 0; v < spec.height; ++v)
    for (int u = 0; u < spec.width; ++u) {
      int g = -1;
      const double z = castPixel(caster, cam, k, u, v, &g);
      ASSERT_EQ(g, wall);
      const size_t i = static_cast<size_t>(v) * spec.width + u;
      if (z < spec.range_max_m - 1e-3) {
        ++near_pixels;
        ASSERT_EQ(view.geom[i], wall) << u << " " << v;
        EXPECT_NEAR(view.depth_m[i], z, 1e-4) << u << " " << v;
        EXPECT_NEAR(img.points[i].z(), z, 1e-4) << u << " " << v;
      } else if (z > cv.far_m + 1e-3) {
        ++far_pixels;
        EXPECT_EQ(view.geom[i], -1) << u << " " << v;
        EXPECT_TRUE(std::isinf(view.depth_m[i])) << u << " " << v;
        EXPECT_TRUE(std::isnan(img.points[i].z())) << u << " " << v;
      } else if (z > spec.range_max_m + 1e-4) {
        EXPECT_TRUE(std::isnan(img.points[i].z())) << u << " " << v;  // drawn, but beyond the camera's range
      }
    }
  EXPECT_GT(near_pixels, spec.width * spec.height / 4);
  EXPECT_GT(far_pixels, spec.width * spec.height / 4);
}

// The exact depth of curved geoms over whole images, seen obliquely: a tilted capsule (side and both ends), an upright
// cylinder (side and top cap) and a sphere, from three poses. Pixels that see the same geom as the ray caster (all but
// the tessellated silhouettes) have its depth within 0.1 mm.
TEST(CameraRenderer, CurvedGeomsHaveTheRayCastersDepthOverTheWholeImage) {
  ts::GeomWriter gw;
  gw.plane("ground", {0, 0, 0}, 20.0, "0.3 0.3 0.3 1");
  gw.capsule("capsule", {1.0, -0.8, 0.2}, {2.2, -0.3, 0.9}, 0.25, "0.8 0.4 0.2 1");
  gw.cylinder("cylinder", {2.0, 0.7, 0.4}, 0.35, 0.4, "0.2 0.4 0.8 1");
  gw.sphere("sphere", {3.2, 0.0, 0.5}, 0.45, "0.9 0.9 0.9 1");
  StaticWorld w(ts::WorldDescription{"curved", gw.str(), 0.0});
  ts::CameraRenderer renderer(w.model.get());
  ts::RayCaster caster(w.model.get(), w.data.get(), -1);
  ts::DepthCameraSpec spec;
  spec.width = 160, spec.height = 120, spec.hfov_rad = 1.2;
  const int curved[3] = {mj_name2id(w.model.get(), mjOBJ_GEOM, "capsule"),
                         mj_name2id(w.model.get(), mjOBJ_GEOM, "cylinder"),
                         mj_name2id(w.model.get(), mjOBJ_GEOM, "sphere")};
  const ts::SensorPose poses[3] = {optical({-0.5, 0.0, 1.6}, {1.0, 0.0, -0.45}, {0, 0, -1}),
                                   optical({1.5, -2.0, 1.2}, {0.3, 1.0, -0.3}, {0, 0, -1}),
                                   optical({4.5, 1.5, 2.0}, {-1.0, -0.6, -0.8}, {0, 0, -1})};
  int on_curved[3] = {0, 0, 0};
  const auto k = ts::intrinsics(spec);
  for (const auto& cam : poses) {
    ts::RenderedView view;
    renderer.render(w.data.get(), cam, viewOf(spec), -1, &view);
    EXPECT_GT(compareWithRayCaster(caster, cam, spec, view).same, 0.99 * spec.width * spec.height);
    double worst_m = 0.0;  // on the curved geoms (the far ground's z-buffer is coarser)
    for (int v = 0; v < spec.height; ++v)
      for (int u = 0; u < spec.width; ++u) {
        int g = -1;
        const double z = castPixel(caster, cam, k, u, v, &g);
        const size_t i = static_cast<size_t>(v) * spec.width + u;
        for (int c = 0; c < 3; ++c)
          if (g == curved[c] && view.geom[i] == g) {
            ++on_curved[c];
            worst_m = std::max(worst_m, std::fabs(view.depth_m[i] - z));
          }
      }
    EXPECT_LT(worst_m, 1e-5);
  }
  for (int i = 0; i < 3; ++i) EXPECT_GT(on_curved[i], 1000) << "geom " << curved[i];
}
