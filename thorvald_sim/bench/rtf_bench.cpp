// Real-time factor (simulated seconds per wall second) of the MuJoCo simulation with in-process base_drivers:
// 1, 2, 4, 8 four-wheel-steered robots driving circles on flat ground; the greenhouse robot with all its sensors
// (lidar 1081 beams at 40 Hz, four ultrasonic cones at 20 Hz, a 640x480 depth camera at 30 Hz, IMU at 100 Hz), in
// the ideal profile and again in the datasheet profile (README, "Sensor models and realism");
// a rover-sized robot in the cotton row with a 1280x720 colour + depth camera at 15 Hz (the cotton paper's ZED
// intrinsics; cotton_camera_rtf.cpp). Then the cost of one camera frame alone. Cameras render through CameraRenderer
// (OSMesa/llvmpipe) with LP_NUM_THREADS=1 unless --render-threads or the environment says otherwise (LP_NUM_THREADS=0:
// llvmpipe rasterises on the calling thread): the figures are single-core. Real-time factors and frame times are given
// per CPU second of this process (the RESULT keys) and per wall second (`_wall`), with the load average, because the
// machine is shared.
//
//   rosrun thorvald_sim rtf_bench [--seconds S] [--sensor-seconds S] [--frames N] [--render-threads N]
#include <CLI/CLI.hpp>
#include <thorvald_common/command_line.h>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <random>
#include <string>
#include <thread>

#include "cotton_camera_rtf.h"
#include "rtf_bench_run.h"
#include "thorvald_sim/camera_renderer.h"

using namespace thorvald_sim;
using namespace rtf_bench;

namespace {

double loadAverage() {
  double l[1] = {0};
  return getloadavg(l, 1) == 1 ? l[0] : -1.0;
}

// The greenhouse robot's scene and its sensors' fixed parts.
struct Greenhouse {
  Run run;
  CameraRenderer renderer;
  RayCaster caster;
  DepthCameraSpec depth;  // 640 x 480, range 0.3 - 6 m
  Greenhouse()
      : run(build(makeGreenhouseWorld(GreenhouseParams(), nullptr), 1, fourWheelSteered(), -3.0, 0.0, options())),
        renderer(run.sim->model()),
        caster(run.sim->model(), run.sim->data(), run.sim->robot(0).root_body) {
    depth.range_max_m = 6.0;
  }
  // The offscreen buffer as the node sizes it: the largest camera image.
  static SceneOptions options() {
    SceneOptions o;
    o.camera_max_width = 640, o.camera_max_height = 480;
    return o;
  }
};

// What the greenhouse sensors cost while the robot drives.
struct SensorLoad {
  Rate rate;
  long beams = 0, depth_frames = 0, us_readings = 0;
  double lidar_cpu = 0.0, cam_cpu = 0.0, us_cpu = 0.0;
};

// Lidar 1081 beams at 40 Hz, four ultrasonic cones at 20 Hz, the depth camera at 30 Hz and the IMU at 100 Hz in the
// `realism` profile (datasheet: default devices, the lidar's sweep from the robot's motion, the IMU's drifting
// state), for `seconds` of a circle.
SensorLoad greenhouseSensors(Greenhouse& gh, Realism realism, double seconds, int image_threads, std::mt19937& rng) {
  LidarSpec lidar;
  lidar.samples = 1081;
  UltrasonicSpec us;
  DepthCameraSpec depth = gh.depth;
  ImuSpec imu;
  lidar.realism = us.realism = depth.realism = imu.realism = realism;
  imu.model = um7ImuModel();
  std::optional<ImuErrors> imu_errors;  // drawn only in the datasheet profile: the ideal run's draws stay as they were
  if (realism == Realism::kDatasheet) imu_errors.emplace(imu.model, rng);
  RenderedView view;
  DepthImage depth_img;
  Every lidar_due(40), us_due(20), cam_due(30), imu_due(100);
  SensorLoad load;
  Eigen::Matrix3d down;
  down << 0, 0, 1, 0, 1, 0, -1, 0, 0;  // x axis pointing down
  Run& run = gh.run;
  const int body = run.sim->robot(0).root_body;
  load.rate = drive(run, seconds, {0.8, 0.0, 0.3}, [&](double t) {
    if (lidar_due.due(t)) {
      const double w = cpuNow();
      const SensorPose pose = mount(run, {0.45, 0, 0.62}, Eigen::Matrix3d::Identity());
      const SensorPose end = sweepEnd(run.sim->model(), run.sim->data(), body, pose, lidar.model.sweep_s);
      load.beams += static_cast<long>(
          simulateLidar(gh.caster, pose, lidar, rng, realism == Realism::kDatasheet ? &end : nullptr).size());
      load.lidar_cpu += cpuNow() - w;
    }
    if (us_due.due(t)) {
      const double w = cpuNow();
      for (double x : {0.52, 0.0})
        for (double y : {-0.3, 0.3})
          simulateUltrasonic(gh.caster, mount(run, {x, y, 0.35}, down), us, rng), ++load.us_readings;
      load.us_cpu += cpuNow() - w;
    }
    if (cam_due.due(t)) {
      const double w = cpuNow();
      const SensorPose cam = mount(run, {0.5, 0, 0.75}, opticalPitched(0.6));
      gh.renderer.render(run.sim->data(), cam, cameraView(depth, false), body, &view, image_threads);
      depthFromView(view, gh.caster, cam, depth, rng, &depth_img, image_threads);
      load.cam_cpu += cpuNow() - w;
      ++load.depth_frames;
    }
    if (imu_due.due(t)) {
      run.sim->updateAccelerations();
      simulateImu(run.sim->model(), run.sim->data(), body, Eigen::Matrix3d::Identity(), imu, rng,
                  imu_errors ? &*imu_errors : nullptr, t);
    }
  });
  return load;
}

void printLoad(const char* scene, const SensorLoad& l) {
  std::printf("%-52s %12.2f %12.2f\n", scene, l.rate.cpu, l.rate.wall);
  std::printf("  (%ld depth frames, %.1f CPU ms each; %ld lidar beams, %.2f CPU ms per 1081-beam scan;\n",
              l.depth_frames, 1e3 * l.cam_cpu / std::max(1L, l.depth_frames), l.beams,
              1e3 * l.lidar_cpu / std::max(1.0, l.beams / 1081.0));
  std::printf("   %ld ultrasonic readings, %.1f CPU us each)\n", l.us_readings,
              1e6 * l.us_cpu / std::max(1L, l.us_readings));
}

}  // namespace

int main(int argc, char** argv) {
  double seconds = 20.0, sensor_seconds = 3.0;
  int frames = 20, render_threads = 1;
  CLI::App app{"Real-time factor of thorvald_sim: flat scenes, the greenhouse robot's sensors, the cotton camera"};
  app.add_option("--seconds", seconds, "simulated seconds per flat scene")->check(CLI::Range(0.1, 3600.0));
  app.add_option("--sensor-seconds", sensor_seconds, "simulated seconds per scene with sensors")
      ->check(CLI::Range(0.1, 3600.0));
  app.add_option("--frames", frames, "camera frames timed alone")->check(CLI::Range(1, 100000));
  app.add_option("--render-threads", render_threads,
                 "llvmpipe threads (LP_NUM_THREADS, unless set in the environment) and image threads; 0: every core")
      ->check(CLI::Range(0, 64));
  if (const auto code = thorvald_common::parseCommandLine(app, argc, argv)) return *code;
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // each line shows as it is done, also when piped
  if (render_threads > 0) setenv("LP_NUM_THREADS", std::to_string(render_threads).c_str(), 0);
  const int image_threads =
      render_threads > 0 ? render_threads : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));

  const double load_start = loadAverage();
  std::printf("load average at start: %.2f (real-time x per CPU second is what one free core would give)\n",
              load_start);
  std::printf("%-52s %12s %12s\n", "scene", "x per CPU s", "x per wall s");
  Rate rtf[9];
  for (int n : {1, 2, 4, 8}) {
    Run run = build(makeFlatWorld(), n, fourWheelSteered(), -3.0, 0.0);
    rtf[n] = drive(run, seconds, {0.8, 0.0, 0.3}, [](double) {});
    std::printf("%-52s %12.1f %12.1f\n", ("flat, " + std::to_string(n) + " robot(s)").c_str(), rtf[n].cpu, rtf[n].wall);
  }

  // The greenhouse robot (sensors_greenhouse.yaml) on the headland, driving a circle, with the ideal sensors, then
  // the same in a second scene with every sensor in the datasheet profile.
  Greenhouse gh;
  std::mt19937 rng(1);
  const SensorLoad ideal_load = greenhouseSensors(gh, Realism::kIdeal, sensor_seconds, image_threads, rng);
  printLoad("greenhouse, lidar + 4 US + 640x480 depth@30Hz + IMU", ideal_load);
  Greenhouse gh_datasheet;
  std::mt19937 rng_datasheet(1);
  const SensorLoad datasheet_load =
      greenhouseSensors(gh_datasheet, Realism::kDatasheet, sensor_seconds, image_threads, rng_datasheet);
  printLoad("greenhouse, the same sensors in the datasheet profile", datasheet_load);
  const Rate rtf_gh = ideal_load.rate, rtf_gh_datasheet = datasheet_load.rate;
  const CottonCameraFigures cotton = cottonCamera(sensor_seconds, frames, image_threads, rng);

  // One greenhouse frame alone: render + depth image, the robot standing where it stopped. Each stage's CPU time
  // too: the render (MuJoCo on OSMesa, read-back, exact depth of curved geoms) and the depth image (range, dropout,
  // grazing angle, noise).
  RenderedView view;
  DepthImage depth_img;
  double stage[2] = {0, 0};
  CameraRenderer::StageTimes render_stages;  // the render's parts, summed over the frames
  const double w = wallNow(), c = cpuNow();
  for (int i = 0; i < frames; ++i) {
    const SensorPose cam = mount(gh.run, {0.5, 0, 0.75}, opticalPitched(0.6));
    timed(&stage[0], [&] {
      gh.renderer.render(gh.run.sim->data(), cam, cameraView(gh.depth, false), gh.run.sim->robot(0).root_body, &view,
                         image_threads);
    });
    const CameraRenderer::StageTimes& t = gh.renderer.lastStageTimes();
    render_stages.scene_s += t.scene_s, render_stages.draw_s += t.draw_s;
    render_stages.readback_s += t.readback_s, render_stages.convert_s += t.convert_s;
    timed(&stage[1], [&] { depthFromView(view, gh.caster, cam, gh.depth, rng, &depth_img, image_threads); });
  }
  const double ms_depth = 1e3 * (cpuNow() - c) / frames, ms_depth_wall = 1e3 * (wallNow() - w) / frames;
  std::printf("%-52s %12s %12s\n", "one camera frame alone", "CPU ms", "wall ms");
  std::printf("%-52s %12.2f %12.2f\n", "640x480 depth (greenhouse)", ms_depth, ms_depth_wall);
  std::printf("  (render %.2f, depth image %.2f CPU ms)\n", 1e3 * stage[0] / frames, 1e3 * stage[1] / frames);
  std::printf("  render of the 640x480 depth: scene %.2f, draw %.2f, read-back %.2f, conversion %.2f CPU ms\n",
              1e3 * render_stages.scene_s / frames, 1e3 * render_stages.draw_s / frames,
              1e3 * render_stages.readback_s / frames, 1e3 * render_stages.convert_s / frames);
  printCottonFrame(cotton, frames);
  const double load_end = loadAverage();
  std::printf("load average at the end: %.2f\n", load_end);
  const char* lp = getenv("LP_NUM_THREADS");
  std::printf("(%.0f s simulated per flat scene, %.0f s per scene with sensors, LP_NUM_THREADS %s, image threads %d)\n",
              seconds, sensor_seconds, lp ? lp : "unset (every core)", image_threads);
  std::printf(
      "RESULT {\"rtf_1_robot\": %.2f, \"rtf_2_robots\": %.2f, \"rtf_4_robots\": %.2f, \"rtf_8_robots\": %.2f, "
      "\"rtf_greenhouse_sensors\": %.3f, \"rtf_cotton_camera\": %.3f, \"ms_per_depth_frame_640x480\": %.2f, "
      "\"ms_per_rgbd_frame_1280x720\": %.2f, \"rtf_1_robot_wall\": %.2f, \"rtf_8_robots_wall\": %.2f, "
      "\"rtf_greenhouse_sensors_wall\": %.3f, \"rtf_cotton_camera_wall\": %.3f, \"load_avg_start\": %.2f, "
      "\"load_avg_end\": %.2f, \"rtf_greenhouse_sensors_datasheet\": %.3f, "
      "\"rtf_greenhouse_sensors_datasheet_wall\": %.3f, \"rtf_cotton_camera_datasheet\": %.3f, "
      "\"rtf_cotton_camera_datasheet_wall\": %.3f, \"cotton_camera\": \"%dx%d@%.0fHz\"}\n",
      rtf[1].cpu, rtf[2].cpu, rtf[4].cpu, rtf[8].cpu, rtf_gh.cpu, cotton.ideal.cpu, ms_depth, cotton.frame_ms,
      rtf[1].wall, rtf[8].wall, rtf_gh.wall, cotton.ideal.wall, load_start, load_end, rtf_gh_datasheet.cpu,
      rtf_gh_datasheet.wall, cotton.datasheet.cpu, cotton.datasheet.wall, CottonCameraFigures::kWidth,
      CottonCameraFigures::kHeight, CottonCameraFigures::kRateHz);
  return 0;
}
