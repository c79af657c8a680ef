// rtf_bench's cotton camera: a rover-sized robot over the cotton row with a 1280x720 colour + depth camera at 15 Hz
// (the cotton paper's ZED intrinsics), in the ideal row and again in the datasheet row (sun, shadows, texture,
// passive stereo), then the cost of one ideal frame alone. Times per CPU second of this process, as rtf_bench.cpp.
#include "cotton_camera_rtf.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "thorvald_sim/cotton_world.h"
#include "thorvald_sim/daylight.h"
#include "thorvald_sim/stereo_models.h"

using namespace thorvald_sim;

namespace rtf_bench {

namespace {

// The cotton rover's size (cotton paper §2.1): axles 0.91 m either side of the centre, 2.12 m wide over 0.30 m
// tyres, wheel radius 0.3048 m. Four steered wheels stand in for its centre articulation here.
thorvald_base::RobotConfig roverSized() {
  thorvald_base::RobotConfig r = fourWheelSteered();
  const double xy[4][2] = {{-0.91, -0.91}, {0.91, -0.91}, {0.91, 0.91}, {-0.91, 0.91}};
  for (int i = 0; i < 4; ++i) {
    r.drives[i].x = xy[i][0], r.drives[i].y = xy[i][1];
    r.drives[i].r_wheel = 0.3048;
    r.drives[i].w_wheel = 0.30;
  }
  return r;
}

struct Zed {
  DepthCameraSpec depth;
  ColorCameraSpec color;
  Zed() {
    depth.width = CottonCameraFigures::kWidth, depth.height = CottonCameraFigures::kHeight;
    depth.focal_px = 699.936, depth.cx_px = 685.286, depth.cy_px = 361.248;
    depth.range_min_m = 0.3, depth.range_max_m = 20.0, depth.noise_coeff = 0.001, depth.dropout = 0.005;
    color.width = depth.width, color.height = depth.height;
    color.focal_px = depth.focal_px, color.cx_px = depth.cx_px, color.cy_px = depth.cy_px;
  }
};

// The camera 2.2 m above the ground looking down, 1.2 m ahead of the rover's centre.
SensorPose zedPose(const Run& run) { return mount(run, {1.2, 0, 2.2}, opticalPitched(M_PI / 2)); }

// The cotton row in the datasheet profile (lobed bolls on springs, springy leaves, clods) under the rover, its ZED
// at 15 Hz as the rover simulation renders it: a sunny day (the dearer case: the sun's shadow map is rendered too),
// the colour shaded with texture, depth from passive stereo; and the IMU at 120 Hz.
void cottonDatasheet(const CottonRowParams& ideal_row, const Zed& zed, double seconds, int image_threads,
                     std::mt19937& rng, CottonCameraFigures* f) {
  CottonRowParams row = ideal_row;
  row.datasheet = true;
  SceneOptions options;
  options.render_slices = kDatasheetRowRenderSlices;  // as the rover's datasheet scene
  Run run = build(makeCottonRowWorld(row, nullptr), 1, roverSized(), 0.3, row.row_y_m, options);
  const mjModel* model = run.sim->model();
  CameraRenderer renderer(model);
  std::vector<float> texture(model->ngeom, 0.0f);
  for (int g = 0; g < model->ngeom; ++g)
    if (const char* name = mj_id2name(model, mjOBJ_GEOM, g)) texture[g] = cottonGeomTexture(name);
  const Daylight sun = sunnyDaylight(0.9, 0.6);
  const Intrinsics k = intrinsics(zed.depth);
  const PassiveStereoModel stereo;
  const int own = run.sim->robot(0).root_body;
  RenderedView view;
  ColorImage rgb;
  std::vector<float> true_z, depth;
  ShadowMapCache shadows;  // the sun's view, rendered again when the camera leaves it or the plants move
  PassiveStereoScratch scratch;
  ImuSpec imu;
  Every camera_due(CottonCameraFigures::kRateHz), imu_due(120);
  double render_s = 0, colour_s = 0, shadow_s = 0, shade_s = 0, stereo_s = 0;
  f->datasheet = drive(run, seconds, {0.1, 0.0, 0.0}, [&](double t) {
    if (camera_due.due(t)) {
      const SensorPose cam = zedPose(run);
      timed(&render_s,
            [&] { renderer.render(run.sim->data(), cam, cameraView(zed.depth, true), own, &view, image_threads); });
      const CameraRenderer::StageTimes& st = renderer.lastStageTimes();
      f->ds_render_stages.scene_s += st.scene_s, f->ds_render_stages.draw_s += st.draw_s;
      f->ds_render_stages.readback_s += st.readback_s, f->ds_render_stages.convert_s += st.convert_s;
      timed(&colour_s, [&] { colorFromView(view, model, zed.color, &rgb); });
      const ShadowMap* shadow = nullptr;
      timed(&shadow_s, [&] {
        shadow =
            &shadows.get(&renderer, model, run.sim->data(), sun, cam.origin + 2.2 * cam.rotation.col(2), 2.1, 720, own);
      });
      timed(&shade_s, [&] { shadeDaylight(view, cam, k, sun, shadow, texture, &rgb); });
      timed(&stereo_s, [&] {
        true_z.resize(view.depth_m.size());
        for (size_t i = 0; i < true_z.size(); ++i) {
          const float z = view.depth_m[i];
          true_z[i] = std::isfinite(z) && z >= zed.depth.range_min_m && z <= zed.depth.range_max_m ? z : std::nanf("");
        }
        passiveStereoDepth(true_z, rgb.rgb, view.width, view.height, k.fx, stereo, rng, &depth, &scratch);
      });
      ++f->datasheet_frames;
    }
    if (imu_due.due(t)) {
      run.sim->updateAccelerations();
      simulateImu(model, run.sim->data(), own, Eigen::Matrix3d::Identity(), imu, rng);
    }
  });
  const double n = std::max(1L, f->datasheet_frames) / 1e3;
  f->ds_render_ms = render_s / n, f->ds_colour_ms = colour_s / n, f->ds_shadow_ms = shadow_s / n;
  f->ds_shade_ms = shade_s / n, f->ds_stereo_ms = stereo_s / n;
  f->shadow_renders = shadows.renders();
  const double camera_s = render_s + colour_s + shadow_s + shade_s + stereo_s;
  if (f->datasheet.cpu > 0.0) f->ds_rest_ms_per_s = 1e3 * (seconds / f->datasheet.cpu - camera_s) / seconds;
}

}  // namespace

CottonCameraFigures cottonCamera(double seconds, int frames, int image_threads, std::mt19937& rng) {
  CottonCameraFigures f;
  // The rover over the ideal cotton row with the ZED at 720p, 2.2 m above the ground looking down, 15 Hz.
  CottonRowParams row;
  const Zed zed;
  Run cotton = build(makeCottonRowWorld(row, nullptr), 1, roverSized(), 0.3, row.row_y_m, SceneOptions());
  CameraRenderer renderer(cotton.sim->model());
  RayCaster caster(cotton.sim->model(), cotton.sim->data(), cotton.sim->robot(0).root_body);
  const int own = cotton.sim->robot(0).root_body;
  RenderedView view;
  DepthImage depth_img;
  ColorImage color_img;
  ImuSpec imu;
  Every zed_due(CottonCameraFigures::kRateHz), imu_due(120);
  long white = 0;
  f.ideal = drive(cotton, seconds, {0.1, 0.0, 0.0}, [&](double t) {
    if (zed_due.due(t)) {
      const SensorPose cam = zedPose(cotton);
      renderer.render(cotton.sim->data(), cam, cameraView(zed.depth, true), own, &view, image_threads);
      depthFromView(view, caster, cam, zed.depth, rng, &depth_img, image_threads);
      colorFromView(view, cotton.sim->model(), zed.color, &color_img);
      for (size_t i = 0; i < color_img.rgb.size(); i += 3)
        white += color_img.rgb[i] == 255 && color_img.rgb[i + 1] == 255;
      ++f.ideal_frames;
    }
    if (imu_due.due(t)) {
      cotton.sim->updateAccelerations();
      simulateImu(cotton.sim->model(), cotton.sim->data(), own, Eigen::Matrix3d::Identity(), imu, rng);
    }
  });
  f.boll_pixels = static_cast<double>(white) / std::max(1L, f.ideal_frames);
  std::printf("%-52s %12.2f %12.2f\n", "cotton row, rover, 1280x720 RGB + depth@15Hz + IMU", f.ideal.cpu, f.ideal.wall);
  std::printf("  (%ld frames, %.0f boll pixels per frame)\n", f.ideal_frames, f.boll_pixels);

  cottonDatasheet(row, zed, seconds, image_threads, rng, &f);
  std::printf("%-52s %12.2f %12.2f\n", "the same in datasheet (sun, shadows, ZED passive stereo)", f.datasheet.cpu,
              f.datasheet.wall);
  std::printf(
      "  (%ld frames of %dx%d at %.0f Hz, CPU ms each: render %.2f, colour %.2f, shadow map %.2f (%ld rendered),\n"
      "   daylight shading %.2f, passive stereo %.2f;\n",
      f.datasheet_frames, CottonCameraFigures::kWidth, CottonCameraFigures::kHeight, CottonCameraFigures::kRateHz,
      f.ds_render_ms, f.ds_colour_ms, f.ds_shadow_ms, f.shadow_renders, f.ds_shade_ms, f.ds_stereo_ms);
  const double dn = std::max(1L, f.datasheet_frames) / 1e3;
  std::printf("   its render: scene %.2f, draw %.2f, read-back %.2f, conversion %.2f CPU ms;\n",
              f.ds_render_stages.scene_s / dn, f.ds_render_stages.draw_s / dn, f.ds_render_stages.readback_s / dn,
              f.ds_render_stages.convert_s / dn);
  std::printf("   besides the camera (physics, IMU): %.0f CPU ms per simulated second)\n", f.ds_rest_ms_per_s);

  // One ideal frame alone: render, depth image (range, dropout, grazing angle, noise) and colour image, the robot
  // standing where it stopped.
  const double w = wallNow(), c = cpuNow();
  for (int i = 0; i < frames; ++i) {
    const SensorPose cam = zedPose(cotton);
    timed(&f.stage_ms[0],
          [&] { renderer.render(cotton.sim->data(), cam, cameraView(zed.depth, true), own, &view, image_threads); });
    const CameraRenderer::StageTimes& t = renderer.lastStageTimes();
    f.render_stages.scene_s += t.scene_s, f.render_stages.draw_s += t.draw_s;
    f.render_stages.readback_s += t.readback_s, f.render_stages.convert_s += t.convert_s;
    timed(&f.stage_ms[1], [&] { depthFromView(view, caster, cam, zed.depth, rng, &depth_img, image_threads); });
    timed(&f.stage_ms[2], [&] { colorFromView(view, cotton.sim->model(), zed.color, &color_img); });
  }
  f.frame_ms = 1e3 * (cpuNow() - c) / frames, f.frame_wall_ms = 1e3 * (wallNow() - w) / frames;
  for (double& s : f.stage_ms) s *= 1e3 / frames;
  return f;
}

void printCottonFrame(const CottonCameraFigures& f, int frames) {
  std::printf("%-52s %12.2f %12.2f\n", "1280x720 RGB + depth (cotton row)", f.frame_ms, f.frame_wall_ms);
  std::printf("  (render %.2f, depth image %.2f, colour image %.2f CPU ms)\n", f.stage_ms[0], f.stage_ms[1],
              f.stage_ms[2]);
  const CameraRenderer::StageTimes& t = f.render_stages;
  std::printf("  render of the 1280x720 RGB + depth: scene %.2f, draw %.2f, read-back %.2f, conversion %.2f CPU ms\n",
              1e3 * t.scene_s / frames, 1e3 * t.draw_s / frames, 1e3 * t.readback_s / frames,
              1e3 * t.convert_s / frames);
}

}  // namespace rtf_bench
