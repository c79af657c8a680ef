// Real-time factor (simulated seconds per wall second) of the MuJoCo simulation with in-process base_drivers:
// 1, 2, 4, 8 four-wheel-steered robots driving circles on flat ground; the greenhouse robot with all its sensors
// (lidar 1081 beams at 40 Hz, four ultrasonic cones at 20 Hz, a 640x480 depth camera at 30 Hz, IMU at 100 Hz), in
// the ideal profile and again in the datasheet profile (README, "Sensor models and realism");
// a rover-sized robot in the cotton row with a 1280x720 colour + depth camera at 15 Hz (the cotton paper's ZED
// intrinsics). Then the cost of one camera frame alone. Cameras render through CameraRenderer (OSMesa/llvmpipe)
// with LP_NUM_THREADS=1 unless --render-threads or the environment says otherwise (LP_NUM_THREADS=0: llvmpipe
// rasterises on the calling thread): the figures are single-core. Real-time factors and
// frame times are given per CPU second of this process (the RESULT keys) and per wall second (`_wall`), with the
// load average, because the machine is shared.
//
//   rosrun thorvald_sim rtf_bench [--seconds S] [--sensor-seconds S] [--frames N] [--render-threads N]
#include <CLI/CLI.hpp>
#include <thorvald_common/command_line.h>
#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <optional>
#include <random>
#include <string>
#include <thread>

#include <thorvald_base/testing/odometry_trial.h>

#include "thorvald_sim/camera_renderer.h"
#include "thorvald_sim/cotton_world.h"
#include "thorvald_sim/daylight.h"
#include "thorvald_sim/stereo_models.h"
#include "thorvald_sim/drive_loop.h"
#include "thorvald_sim/sensors.h"
#include "thorvald_sim/testing/reference_urdf.h"
#include "thorvald_sim/world.h"

using namespace thorvald_sim;

namespace {

thorvald_base::RobotConfig fourWheelSteered() {
  thorvald_base::RobotConfig r = thorvald_base::figure7Robot();
  r.drives.resize(4);
  const double xy[4][2] = {{-0.675, -0.6}, {0.675, -0.6}, {0.675, 0.6}, {-0.675, 0.6}};
  for (int i = 0; i < 4; ++i) r.drives[i].x = xy[i][0], r.drives[i].y = xy[i][1];
  return r;
}

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

struct Run {
  std::unique_ptr<Simulation> sim;
  std::vector<std::unique_ptr<DrivenRobot>> robots;
};

Run build(const WorldDescription& world, int n, const thorvald_base::RobotConfig& robot, double x, double y,
          const SceneOptions& options = SceneOptions()) {
  Run run;
  std::vector<RobotSpawn> spawns;
  for (int i = 0; i < n; ++i) {
    RobotSpawn s;
    s.name = "robot" + std::to_string(i);
    s.mjcf = urdfToMjcf(referenceUrdf(robot, s.name), &s.root_link);
    s.x = x;
    s.y = y + 5.0 * i;
    s.z = 0.01;
    spawns.push_back(s);
  }
  run.sim = std::make_unique<Simulation>(composeScene(world, spawns, options), spawns);
  for (int i = 0; i < n; ++i) run.robots.push_back(std::make_unique<DrivenRobot>(*run.sim, robot, spawns[i].name));
  return run;
}

// The machine is shared: besides wall time, the CPU time this process got (all its threads) tells what one free
// core would do.
double wallNow() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }
double cpuNow() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

// Simulated seconds per wall second and per CPU second.
struct Rate {
  double wall = 0, cpu = 0;
};

double loadAverage() {
  double l[1] = {0};
  return getloadavg(l, 1) == 1 ? l[0] : -1.0;
}

// Drives every robot with `cmd` for `seconds` of simulated time at 50 Hz control; `sensors` runs each cycle.
Rate drive(Run& run, double seconds, const thorvald_base::Twist2D& cmd, const std::function<void(double)>& sensors) {
  const int steps = static_cast<int>(std::lround(0.02 / run.sim->timestep()));
  const double t0 = run.sim->time(), w0 = wallNow(), c0 = cpuNow();
  while (run.sim->time() - t0 < seconds) {
    const double t = run.sim->time();
    for (auto& r : run.robots) {
      r->command(cmd, t);
      r->control(t);
    }
    run.sim->step(steps);
    sensors(run.sim->time());
  }
  return {(run.sim->time() - t0) / (wallNow() - w0), (run.sim->time() - t0) / (cpuNow() - c0)};
}

// A sensor mounted on robot 0's base_link.
SensorPose mount(const Run& run, const Eigen::Vector3d& xyz, const Eigen::Matrix3d& r) {
  const BodyState b = run.sim->robotState(0);
  SensorPose p;
  p.origin = b.position + b.orientation * xyz;
  p.rotation = b.orientation.toRotationMatrix() * r;
  return p;
}

// Optical frame (z forward, x right, y down) of a camera pitched `pitch` down from looking forward.
Eigen::Matrix3d opticalPitched(double pitch) {
  return Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()).toRotationMatrix() *
         (Eigen::Matrix3d() << 0, 0, 1, -1, 0, 0, 0, -1, 0).finished();
}

// Calls `f` at `rate_hz` in simulated time.
struct Every {
  double period, next = 0.0;
  explicit Every(double rate_hz) : period(1.0 / rate_hz) {}
  bool due(double t) {
    if (t + 1e-9 < next) return false;
    next = std::max(next + period, t);
    return true;
  }
};

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

// The cotton row in the datasheet profile (lobed bolls on springs, springy leaves, clods) under the rover, its ZED
// at 15 Hz as the rover simulation renders it: a sunny day (the dearer case: the sun's shadow map is rendered too),
// the colour shaded with texture, depth from passive stereo; and the IMU at 120 Hz.
Rate cottonDatasheet(const CottonRowParams& ideal_row, const SceneOptions& options, const DepthCameraSpec& zed,
                     const ColorCameraSpec& zed_color, double seconds, int image_threads, std::mt19937& rng) {
  CottonRowParams row = ideal_row;
  row.datasheet = true;
  Run run = build(makeCottonRowWorld(row, nullptr), 1, roverSized(), 0.3, row.row_y_m, options);
  const mjModel* model = run.sim->model();
  CameraRenderer renderer(model);
  std::vector<float> texture(model->ngeom, 0.0f);
  for (int g = 0; g < model->ngeom; ++g)
    if (const char* name = mj_id2name(model, mjOBJ_GEOM, g)) texture[g] = cottonGeomTexture(name);
  const Daylight sun = sunnyDaylight(0.9, 0.6);
  const Intrinsics k = intrinsics(zed);
  const PassiveStereoModel stereo;
  const int own = run.sim->robot(0).root_body;
  RenderedView view;
  ColorImage rgb;
  std::vector<float> true_z;
  ImuSpec imu;
  Every camera_due(15), imu_due(120);
  return drive(run, seconds, {0.1, 0.0, 0.0}, [&](double t) {
    if (camera_due.due(t)) {
      const SensorPose cam = mount(run, {1.2, 0, 2.2}, opticalPitched(M_PI / 2));
      renderer.render(run.sim->data(), cam, cameraView(zed, true), own, &view, image_threads);
      colorFromView(view, model, zed_color, &rgb);
      const ShadowMap shadow =
          renderShadowMap(&renderer, run.sim->data(), sun, cam.origin + 2.2 * cam.rotation.col(2), 2.1, 720, own);
      shadeDaylight(view, cam, k, sun, &shadow, texture, &rgb);
      true_z.resize(view.depth_m.size());
      for (size_t i = 0; i < true_z.size(); ++i) {
        const float z = view.depth_m[i];
        true_z[i] = std::isfinite(z) && z >= zed.range_min_m && z <= zed.range_max_m ? z : std::nanf("");
      }
      passiveStereoDepth(true_z, rgb.rgb, view.width, view.height, k.fx, stereo, rng);
    }
    if (imu_due.due(t)) {
      run.sim->updateAccelerations();
      simulateImu(model, run.sim->data(), own, Eigen::Matrix3d::Identity(), imu, rng);
    }
  });
}

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
  RayCaster& caster = gh.caster;
  CameraRenderer& gh_renderer = gh.renderer;
  DepthCameraSpec& depth = gh.depth;
  RenderedView view;
  DepthImage depth_img;
  ColorImage color_img;
  ImuSpec imu;

  // The rover over the cotton row with the ZED at 720p, 2.2 m above the ground looking down, 15 Hz.
  CottonRowParams row;
  SceneOptions cotton_options;
  Run cotton = build(makeCottonRowWorld(row, nullptr), 1, roverSized(), 0.3, row.row_y_m, cotton_options);
  CameraRenderer cotton_renderer(cotton.sim->model());
  RayCaster cotton_caster(cotton.sim->model(), cotton.sim->data(), cotton.sim->robot(0).root_body);
  DepthCameraSpec zed;
  zed.width = 1280, zed.height = 720;
  zed.focal_px = 699.936, zed.cx_px = 685.286, zed.cy_px = 361.248;
  zed.range_min_m = 0.3, zed.range_max_m = 20.0, zed.noise_coeff = 0.001, zed.dropout = 0.005;
  ColorCameraSpec zed_color;
  zed_color.width = zed.width, zed_color.height = zed.height;
  zed_color.focal_px = zed.focal_px, zed_color.cx_px = zed.cx_px, zed_color.cy_px = zed.cy_px;
  Every zed_due(15), cotton_imu_due(120);
  long zed_frames = 0;
  long white = 0;
  const Rate rtf_cotton = drive(cotton, sensor_seconds, {0.1, 0.0, 0.0}, [&](double t) {
    if (zed_due.due(t)) {
      const SensorPose cam = mount(cotton, {1.2, 0, 2.2}, opticalPitched(M_PI / 2));
      cotton_renderer.render(cotton.sim->data(), cam, cameraView(zed, true), cotton.sim->robot(0).root_body, &view,
                             image_threads);
      depthFromView(view, cotton_caster, cam, zed, rng, &depth_img, image_threads);
      colorFromView(view, cotton.sim->model(), zed_color, &color_img);
      for (size_t i = 0; i < color_img.rgb.size(); i += 3)
        white += color_img.rgb[i] == 255 && color_img.rgb[i + 1] == 255;
      ++zed_frames;
    }
    if (cotton_imu_due.due(t)) {
      cotton.sim->updateAccelerations();
      simulateImu(cotton.sim->model(), cotton.sim->data(), cotton.sim->robot(0).root_body, Eigen::Matrix3d::Identity(),
                  imu, rng);
    }
  });
  std::printf("%-52s %12.2f %12.2f\n", "cotton row, rover, 1280x720 RGB + depth@15Hz + IMU", rtf_cotton.cpu,
              rtf_cotton.wall);
  std::printf("  (%ld frames, %.0f boll pixels per frame)\n", zed_frames,
              static_cast<double>(white) / std::max(1L, zed_frames));
  const Rate rtf_cotton_ds = cottonDatasheet(row, cotton_options, zed, zed_color, sensor_seconds, image_threads, rng);
  std::printf("%-52s %12.2f %12.2f\n", "the same in datasheet (sun, shadows, ZED passive stereo)", rtf_cotton_ds.cpu,
              rtf_cotton_ds.wall);

  // One frame alone: render + depth image (+ colour image), the robots standing where they stopped.
  // Each stage's CPU time too: the render (MuJoCo on OSMesa, read-back, exact depth of curved geoms), the depth image
  // (range, dropout, grazing angle, noise) and the colour image.
  double stage[2][3] = {{0, 0, 0}, {0, 0, 0}};
  CameraRenderer::StageTimes render_stages[2];  // the render's parts, summed over the frames
  auto addStages = [](CameraRenderer::StageTimes* sum, const CameraRenderer::StageTimes& t) {
    sum->scene_s += t.scene_s, sum->draw_s += t.draw_s, sum->readback_s += t.readback_s, sum->convert_s += t.convert_s;
  };
  auto timed = [](double* acc, const std::function<void()>& f) {
    const double c0 = cpuNow();
    f();
    *acc += cpuNow() - c0;
  };
  double w = wallNow(), c = cpuNow();
  for (int i = 0; i < frames; ++i) {
    const SensorPose cam = mount(gh.run, {0.5, 0, 0.75}, opticalPitched(0.6));
    timed(&stage[0][0], [&] {
      gh_renderer.render(gh.run.sim->data(), cam, cameraView(depth, false), gh.run.sim->robot(0).root_body, &view,
                         image_threads);
    });
    addStages(&render_stages[0], gh_renderer.lastStageTimes());
    timed(&stage[0][1], [&] { depthFromView(view, caster, cam, depth, rng, &depth_img, image_threads); });
  }
  const double ms_depth = 1e3 * (cpuNow() - c) / frames, ms_depth_wall = 1e3 * (wallNow() - w) / frames;
  w = wallNow(), c = cpuNow();
  for (int i = 0; i < frames; ++i) {
    const SensorPose cam = mount(cotton, {1.2, 0, 2.2}, opticalPitched(M_PI / 2));
    timed(&stage[1][0], [&] {
      cotton_renderer.render(cotton.sim->data(), cam, cameraView(zed, true), cotton.sim->robot(0).root_body, &view,
                             image_threads);
    });
    addStages(&render_stages[1], cotton_renderer.lastStageTimes());
    timed(&stage[1][1], [&] { depthFromView(view, cotton_caster, cam, zed, rng, &depth_img, image_threads); });
    timed(&stage[1][2], [&] { colorFromView(view, cotton.sim->model(), zed_color, &color_img); });
  }
  const double ms_rgbd = 1e3 * (cpuNow() - c) / frames, ms_rgbd_wall = 1e3 * (wallNow() - w) / frames;
  std::printf("%-52s %12s %12s\n", "one camera frame alone", "CPU ms", "wall ms");
  std::printf("%-52s %12.2f %12.2f\n", "640x480 depth (greenhouse)", ms_depth, ms_depth_wall);
  std::printf("  (render %.2f, depth image %.2f CPU ms)\n", 1e3 * stage[0][0] / frames, 1e3 * stage[0][1] / frames);
  std::printf("%-52s %12.2f %12.2f\n", "1280x720 RGB + depth (cotton row)", ms_rgbd, ms_rgbd_wall);
  std::printf("  (render %.2f, depth image %.2f, colour image %.2f CPU ms)\n", 1e3 * stage[1][0] / frames,
              1e3 * stage[1][1] / frames, 1e3 * stage[1][2] / frames);
  for (int i = 0; i < 2; ++i) {
    const CameraRenderer::StageTimes& t = render_stages[i];
    std::printf("  render of the %s: scene %.2f, draw %.2f, read-back %.2f, conversion %.2f CPU ms\n",
                i == 0 ? "640x480 depth" : "1280x720 RGB + depth", 1e3 * t.scene_s / frames, 1e3 * t.draw_s / frames,
                1e3 * t.readback_s / frames, 1e3 * t.convert_s / frames);
  }
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
      "\"rtf_cotton_camera_datasheet_wall\": %.3f}\n",
      rtf[1].cpu, rtf[2].cpu, rtf[4].cpu, rtf[8].cpu, rtf_gh.cpu, rtf_cotton.cpu, ms_depth, ms_rgbd, rtf[1].wall,
      rtf[8].wall, rtf_gh.wall, rtf_cotton.wall, load_start, load_end, rtf_gh_datasheet.cpu, rtf_gh_datasheet.wall,
      rtf_cotton_ds.cpu, rtf_cotton_ds.wall);
  return 0;
}
