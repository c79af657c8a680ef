// The cotton row and camera in `datasheet`: each plant feature is in the generated world and behaves (lobes and
// bracts, half-open bolls, springy leaves, rigid stems, bolls that break off), the sun's hard shadows, and the ZED's
// passive-stereo depth with holes on a textureless surface. Each test fails without its feature.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <thorvald_sim/camera_images.h>
#include <thorvald_sim/cotton_world.h>
#include <thorvald_sim/daylight.h>

#include "cotton_harvester_sim/harvest_run.h"

using namespace cotton_harvester;
namespace ts = thorvald_sim;

namespace {

ts::CottonRowParams datasheetRow(int plants) {
  ts::CottonRowParams p;
  p.plants = plants;
  p.datasheet = true;
  p.leaf_over_boll_fraction = 0.4;
  return p;
}

/// The row with `extra` bodies after it, compiled.
ts::ModelPtr compileRow(const ts::CottonRowParams& p, const std::string& extra = "",
                        const std::string& actuators = "") {
  const ts::WorldDescription w = ts::makeCottonRowWorld(p, nullptr);
  const std::string xml =
      "<mujoco><compiler angle=\"radian\"/><option timestep=\"0.002\" integrator=\"Euler\"/>"
      "<visual><global offwidth=\"1280\" offheight=\"720\"/><quality offsamples=\"0\"/></visual><worldbody>" +
      w.worldbody + extra + "</worldbody>" + actuators + "</mujoco>";
  return ts::compileXml(xml, "cotton realism test");
}

int countGeoms(const mjModel* m, const std::string& prefix, const std::string& part) {
  int n = 0;
  for (int g = 0; g < m->ngeom; ++g) {
    const char* name = mj_id2name(m, mjOBJ_GEOM, g);
    if (!name) continue;
    const std::string s(name);
    n += s.rfind(prefix, 0) == 0 && s.find(part) != std::string::npos ? 1 : 0;
  }
  return n;
}

/// A box pusher on a slide joint along world y at (x, y0, z), driven by a force-limited position actuator; it meets
/// the plants like the end-effector's housing.
std::string pusher(const Eigen::Vector3d& at) {
  std::ostringstream s;
  s << "<body name=\"pusher\" pos=\"" << at.x() << " " << at.y() << " " << at.z() << "\">"
    << "<joint name=\"push\" type=\"slide\" axis=\"0 1 0\" damping=\"300\"/>"
    << "<geom type=\"box\" size=\"0.05 0.05 0.04\" mass=\"3\" contype=\"0\" conaffinity=\""
    << (ts::kPlantContype | ts::kStemContype | ts::kBollContype)
    << "\" solref=\"0.004 1\" solimp=\"0.95 0.99 0.001\"/></body>";
  return s.str();
}

}  // namespace

TEST(CottonRealism, BollsHaveLobesAndBractsAndSomeAreHalfOpen) {
  ts::CottonRowTruth truth;
  ts::CottonRowParams p = datasheetRow(6);
  ts::makeCottonRowWorld(p, &truth);
  const ts::ModelPtr m = compileRow(p);
  EXPECT_EQ(countGeoms(m.get(), "plant0_boll0", "_lobe"), 5);
  EXPECT_EQ(countGeoms(m.get(), "plant0_boll0", "_bract"), 5);
  EXPECT_GT(countGeoms(m.get(), "plant", "_dry"), 0);
  EXPECT_GT(countGeoms(m.get(), "plant", "_burr"), 0);
  EXPECT_GT(countGeoms(m.get(), "clod", ""), 50);
  EXPECT_GT(countGeoms(m.get(), "weed", ""), 10);
  int half_open = 0;
  for (char h : truth.boll_half_open) half_open += h;
  EXPECT_GT(half_open, 0);
  EXPECT_LT(half_open, static_cast<int>(truth.bolls.size()));
  // Plants of different heights: the stems' tops differ.
  std::vector<double> tops;
  for (int i = 0; i < p.plants; ++i) {
    const int g = mj_name2id(m.get(), mjOBJ_GEOM, ("plant" + std::to_string(i) + "_stem").c_str());
    ASSERT_GE(g, 0);
    tops.push_back(m->geom_pos[3 * g + 2] + m->geom_size[3 * g + 1]);
  }
  EXPECT_GT(*std::max_element(tops.begin(), tops.end()) - *std::min_element(tops.begin(), tops.end()), 0.03);
  // Ideal keeps today's flat plants.
  ts::CottonRowParams ideal = p;
  ideal.datasheet = false;
  const ts::ModelPtr mi = compileRow(ideal);
  EXPECT_EQ(countGeoms(mi.get(), "plant", "_lobe"), 0);
  EXPECT_EQ(mi->nbody, 1);
}

TEST(CottonRealism, LeafPushedByAForceSpringsBack) {
  const ts::ModelPtr m = compileRow(datasheetRow(1));
  ts::DataPtr d(mj_makeData(m.get()));
  const int j = mj_name2id(m.get(), mjOBJ_JOINT, "plant0_leaf0_pitch");
  ASSERT_GE(j, 0);
  const int dof = m->jnt_dofadr[j], q = m->jnt_qposadr[j];
  for (int i = 0; i < 150; ++i) {  // 0.3 s pushed down with 0.02 N m
    d->qfrc_applied[dof] = 0.02;
    mj_step(m.get(), d.get());
  }
  const double pushed = d->qpos[q];
  EXPECT_GT(std::abs(pushed), 0.3);
  d->qfrc_applied[dof] = 0.0;
  for (int i = 0; i < 500; ++i) mj_step(m.get(), d.get());
  EXPECT_LT(std::abs(d->qpos[q]), 0.1 * std::abs(pushed));  // back near its rest angle, not left bent
}

TEST(CottonRealism, StemStopsAMovingBody) {
  ts::CottonRowParams p = datasheetRow(1);
  p.leaves_per_plant = 0;
  p.bolls_per_plant = 0;
  p.realism.dry_leaves_per_plant = p.realism.burrs_per_plant = 0;
  ts::CottonRowTruth truth;
  ts::makeCottonRowWorld(p, &truth);
  const Eigen::Vector3d base = truth.plant_bases[0];
  const ts::ModelPtr m = compileRow(p, pusher(base + Eigen::Vector3d(0, -0.3, 0.3)),
                                    "<actuator><position joint=\"push\" kp=\"100000\" forcelimited=\"true\" "
                                    "forcerange=\"-1500 1500\"/></actuator>");
  ts::DataPtr d(mj_makeData(m.get()));
  const int q = m->jnt_qposadr[mj_name2id(m.get(), mjOBJ_JOINT, "push")];
  d->ctrl[0] = 0.6;  // aims 30 cm past the stem
  for (int i = 0; i < 1500; ++i) mj_step(m.get(), d.get());
  const double y_then = base.y() - 0.3 + d->qpos[q];
  for (int i = 0; i < 500; ++i) mj_step(m.get(), d.get());
  const double y = base.y() - 0.3 + d->qpos[q];
  // The box's face (5 cm from its centre) rests on the stem (8 mm radius), sunk in by the contact's softness under
  // the 1500 N push (under 3 cm), and stays there (but for a slow creep).
  EXPECT_LT(y, base.y() - 0.05 + 0.03);
  EXPECT_GT(y, base.y() - 0.1);   // it did move up to the stem
  EXPECT_NEAR(y, y_then, 0.005);  // creeps by a few mm/s: the soft contact
}

TEST(CottonRealism, HousingKnocksABollOff) {
  sim::RoverSimParams p = sim::pottedConfig(1).sim;
  p.realism = ts::Realism::kDatasheet;
  p.row.plants = 1;
  p.row.leaves_per_plant = 0;
  // Stand the rover so that the arm's plane crosses a boll on the arm's side of the stem.
  ts::CottonRowParams row = p.row;
  row.datasheet = true;
  ts::CottonRowTruth truth;
  ts::makeCottonRowWorld(row, &truth);
  size_t target = 0;
  for (size_t i = 0; i < truth.bolls.size(); ++i)
    if (truth.bolls[i].y() < truth.bolls[target].y()) target = i;
  ASSERT_LT(truth.bolls[target].y(), -0.03);
  p.start_x_m = truth.bolls[target].x() - p.geometry.camera_ahead_m;
  sim::RoverSim s(p);
  const Eigen::Vector3d c = s.toCamera(s.bolls()[target].centre);
  s.commandHorizontal(0.0);
  s.advance(2.5);
  s.commandVertical(c.z() - 0.5 * p.geometry.effector_height_m);
  s.advance(4.0);
  ASSERT_FALSE(s.bolls()[target].knocked_off);
  s.commandHorizontal(c.x() + p.geometry.arm_base_offset_m + 0.08);  // through the boll, towards the stem
  s.advance(3.0);
  EXPECT_TRUE(s.bolls()[target].knocked_off);
  EXPECT_EQ(s.bollsKnockedOff(), 1);
  s.commandHorizontal(0.0);
  s.advance(2.0);
  EXPECT_GT((s.bolls()[target].centre - truth.bolls[target]).norm(), 0.05);  // it fell or was carried off
}

TEST(CottonRealism, SunCastsHardShadowsOvercastDoesNot) {
  // A box 0.3 m above a grey ground; the sun at 60 deg elevation along +x; the camera 2 m up looking down.
  const std::string xml =
      "<mujoco><visual><global offwidth=\"720\" offheight=\"720\"/><quality offsamples=\"0\"/></visual><worldbody>"
      "<geom name=\"ground\" type=\"plane\" size=\"5 5 0.1\" rgba=\"0.5 0.5 0.5 1\"/>"
      "<geom name=\"roof\" type=\"box\" pos=\"0 0 0.3\" size=\"0.1 0.1 0.01\" rgba=\"0.5 0.5 0.5 1\"/>"
      "</worldbody></mujoco>";
  const ts::ModelPtr m = ts::compileXml(xml, "shadow test");
  ts::DataPtr d(mj_makeData(m.get()));
  mj_forward(m.get(), d.get());
  ts::CameraRenderer renderer(m.get());
  ts::SensorPose pose;
  pose.origin = Eigen::Vector3d(0, 0, 2.0);
  pose.rotation << 1, 0, 0, 0, -1, 0, 0, 0, -1;  // x right = world x, y down = world -y, z forward = down
  ts::CameraView view;
  view.width = view.height = 200;
  view.k = ts::Intrinsics{200, 200, 99.5, 99.5};
  view.near_m = 0.1;
  view.far_m = 5.0;
  ts::RenderedView rendered;
  renderer.render(d.get(), pose, view, -1, &rendered);
  ts::ColorCameraSpec spec;
  spec.width = spec.height = 200;
  spec.focal_px = 200;
  spec.cx_px = spec.cy_px = 99.5;
  const std::vector<float> texture(m->ngeom, 0.0f);
  auto shade = [&](const ts::Daylight& light) {
    ts::ColorImage rgb = ts::colorFromView(rendered, m.get(), spec);
    const ts::ShadowMap shadow = ts::renderShadowMap(&renderer, d.get(), light, Eigen::Vector3d::Zero(), 1.0, 512, -1);
    ts::shadeDaylight(rendered, pose, view.k, light, &shadow, texture, &rgb);
    return rgb;
  };
  const ts::Daylight sunny = ts::sunnyDaylight(M_PI / 3, 0.0), overcast = ts::overcastDaylight(M_PI / 3, 0.0);
  const ts::ColorImage a = shade(sunny), b = shade(overcast);
  // The roof's shadow on the ground: 0.3 m / tan(60 deg) = 0.17 m towards -x of the box.
  const Eigen::Vector3d shade_point(-0.3 / std::tan(M_PI / 3), 0.0, 0.0), open_point(0.5, 0.3, 0.0);
  auto pixel = [&](const ts::ColorImage& img, const Eigen::Vector3d& w) {
    const Eigen::Vector3d c = pose.rotation.transpose() * (w - pose.origin);
    const int u = static_cast<int>(std::lround(200 * c.x() / c.z() + 99.5));
    const int v = static_cast<int>(std::lround(200 * c.y() / c.z() + 99.5));
    return static_cast<int>(img.rgb[3 * (static_cast<size_t>(v) * 200 + u)]);
  };
  EXPECT_LT(pixel(a, shade_point), pixel(b, shade_point) - 30);  // in the shadow: darker under the sun
  EXPECT_LT(pixel(a, shade_point), pixel(a, open_point) - 40);   // than the sunlit ground next to it
  EXPECT_NEAR(pixel(b, shade_point), pixel(b, open_point), 3);   // overcast: no hard shadow
}

// ShadowMapCache: the map is rendered again only when the asked region leaves it, a geom moves or is hidden, or the
// day changes; a kept map, and one rendered in bands (taller than the renderer's buffer), shade as a fresh one does.
TEST(CottonRealism, ShadowMapIsKeptUntilTheSceneOrTheRegionChanges) {
  auto scene = [](int offheight) {
    return "<mujoco><visual><global offwidth=\"720\" offheight=\"" + std::to_string(offheight) +
           "\"/><quality offsamples=\"0\"/></visual><worldbody>"
           "<geom name=\"ground\" type=\"plane\" size=\"5 5 0.1\" rgba=\"0.5 0.5 0.5 1\"/>"
           "<geom name=\"roof\" type=\"box\" pos=\"0 0 0.3\" size=\"0.1 0.1 0.01\" rgba=\"0.5 0.5 0.5 1\"/>"
           "</worldbody></mujoco>";
  };
  const ts::ModelPtr m = ts::compileXml(scene(720), "shadow cache test");
  const ts::ModelPtr low = ts::compileXml(scene(300), "shadow cache test, low buffer");
  ts::DataPtr d(mj_makeData(m.get())), dl(mj_makeData(low.get()));
  mj_forward(m.get(), d.get());
  mj_forward(low.get(), dl.get());
  ts::CameraRenderer renderer(m.get()), low_renderer(low.get());
  const ts::Daylight sun = ts::sunnyDaylight(M_PI / 3, 0.0);
  const ts::ShadowMap fresh = ts::renderShadowMap(&renderer, d.get(), sun, Eigen::Vector3d::Zero(), 1.0, 512, -1);
  ts::ShadowMapCache cache, banded;
  const ts::ShadowMap& kept = cache.get(&renderer, m.get(), d.get(), sun, Eigen::Vector3d::Zero(), 1.0, 512, -1);
  const ts::ShadowMap& bands =
      banded.get(&low_renderer, low.get(), dl.get(), sun, Eigen::Vector3d::Zero(), 1.0, 512, -1);
  EXPECT_GT(kept.view.width, 512);  // the margin around the asked square
  EXPECT_EQ(bands.view.height, kept.view.height);
  int shaded = 0, differ_kept = 0, differ_bands = 0;
  for (double x = -0.9; x <= 0.9; x += 0.01)
    for (double y = -0.9; y <= 0.9; y += 0.01) {
      const Eigen::Vector3d p(x, y, 0.0);
      const bool lit = ts::litBySun(fresh, p, sun.shadow_bias_m);
      shaded += !lit;
      differ_kept += ts::litBySun(kept, p, sun.shadow_bias_m) != lit;
      differ_bands += ts::litBySun(bands, p, sun.shadow_bias_m) != lit;
    }
  EXPECT_GT(shaded, 300);      // the roof's shadow: 0.2 m x 0.2 m at 1 cm steps
  EXPECT_LE(differ_kept, 2);   // the same pixel grid; only the depth range (z-buffer steps of microns) differs
  EXPECT_LE(differ_bands, 2);  // the same pixel grid; a band's edge may round one pixel differently
  // Kept while the asked square moves within the margin; rendered again beyond it.
  cache.get(&renderer, m.get(), d.get(), sun, Eigen::Vector3d(0.2, 0.1, 0.0), 1.0, 512, -1);
  EXPECT_EQ(cache.renders(), 1);
  cache.get(&renderer, m.get(), d.get(), sun, Eigen::Vector3d(1.5, 0.0, 0.0), 1.0, 512, -1);
  EXPECT_EQ(cache.renders(), 2);
  // A geom that moves, one that is hidden, another sun: rendered again.
  m->geom_pos[3 * 1] += 0.05;
  mj_forward(m.get(), d.get());
  cache.get(&renderer, m.get(), d.get(), sun, Eigen::Vector3d(1.5, 0.0, 0.0), 1.0, 512, -1);
  EXPECT_EQ(cache.renders(), 3);
  cache.get(&renderer, m.get(), d.get(), sun, Eigen::Vector3d(1.5, 0.0, 0.0), 1.0, 512, -1);
  EXPECT_EQ(cache.renders(), 3);
  m->geom_rgba[4 * 1 + 3] = 0.0f;
  cache.get(&renderer, m.get(), d.get(), sun, Eigen::Vector3d(1.5, 0.0, 0.0), 1.0, 512, -1);
  EXPECT_EQ(cache.renders(), 4);
  cache.get(&renderer, m.get(), d.get(), ts::sunnyDaylight(M_PI / 4, 0.0), Eigen::Vector3d(1.5, 0, 0), 1.0, 512, -1);
  EXPECT_EQ(cache.renders(), 5);
  EXPECT_FALSE(
      cache.get(&renderer, m.get(), d.get(), ts::overcastDaylight(M_PI / 4, 0.0), Eigen::Vector3d::Zero(), 1.0, 512, -1)
          .valid);
}

TEST(CottonRealism, DatasheetDepthHasHolesOnTheTexturelessHousing) {
  sim::RoverSimParams p = sim::pottedConfig(2).sim;
  p.row.plants = 2;
  p.realism = ts::Realism::kDatasheet;
  sim::RoverSim s(p);
  s.setDaylight(ts::overcastDaylight(1.0, 0.5));  // no saturation: the holes come from the missing texture
  cv::Mat bgr, cloud;
  s.renderCamera(&bgr, &cloud);
  const Eigen::Vector3d n = s.toCamera(s.nozzlePosition());
  const int u0 = static_cast<int>(p.cx + p.fx * n.x() / n.z()), v0 = static_cast<int>(p.cy + p.fx * n.y() / n.z());
  int holes = 0, pixels = 0;
  for (int v = v0 - 10; v <= v0 + 10; ++v)
    for (int u = u0 - 10; u <= u0 + 10; ++u, ++pixels) holes += std::isnan(cloud.at<cv::Vec3f>(v, u)[2]) ? 1 : 0;
  EXPECT_GT(holes, 0.8 * pixels);  // the uniform orange housing: no match
  int soil_valid = 0, soil = 0;
  for (int v = 560; v < 700; ++v)  // soil between the rover's left rail and the row
    for (int u = 420; u < 560; ++u, ++soil) soil_valid += std::isfinite(cloud.at<cv::Vec3f>(v, u)[2]) ? 1 : 0;
  EXPECT_GT(soil_valid, 0.5 * soil);  // textured soil and plants: matched
  // Ideal: depth on the housing as ever.
  p.realism = ts::Realism::kIdeal;
  sim::RoverSim ideal(p);
  ideal.renderCamera(&bgr, &cloud);
  EXPECT_TRUE(std::isfinite(cloud.at<cv::Vec3f>(v0, u0)[2]));
}
