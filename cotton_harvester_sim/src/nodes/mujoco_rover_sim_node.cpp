// mujoco_rover_sim: the cotton rover and its row in MuJoCo as the harvest stack's nodes see a real rover. The
// navigation and manipulation controllers answer on pseudo-terminals with the hardware's byte protocols (the `rover`
// and `manipulator` nodes open them as serial devices), the downward camera is published as the ZED driver publishes
// it (colour image, organised cloud, camera info), the localisation sensors as their drivers publish them (two IMUs,
// the encoders and potentiometer, the RTK receiver's NMEA for gpsd: rover_sensor_topics.h), and the simulated time
// as /clock. It is also the run's scorer, the only node that reads the simulator's truth (sim/truth/base_link is
// for tests' scoring): when the harvest machine reports that its run ended (or at the time limit) it counts the
// bolls the vacuum took, publishes harvest/metrics, appends the CSV row and exits 0 (1 when the world or the ports
// cannot be made). The node only wires its parts: the simulation (RoverSim), the serial devices
// (RoverDeviceEmulator), the camera's messages (rover_camera_messages.h), the sensors' topics (RoverSensorTopics),
// what the stack reports (StackRunReport) and the scorer (HarvestScorer). With ~harvest false it only simulates.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <diagnostic_msgs/DiagnosticStatus.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <thorvald_common/ros/param_reader.h>
#include <thorvald_state_machine/MachineStatus.h>

#include "cotton_harvester/BollArray.h"
#include "cotton_harvester/control/harvest_metrics.h"
#include "cotton_harvester_sim/harvest_run.h"
#include "cotton_harvester_sim/harvest_scorer.h"
#include "cotton_harvester_sim/rover_device_emulator.h"
#include "cotton_harvester_sim/stack_run_report.h"
#include "harvest_metrics_status.h"
#include "rover_camera_messages.h"
#include "rover_sensor_topics.h"

namespace cotton_harvester {
namespace sim {
namespace {

using thorvald_common::ParamRange;

struct SimNodeConfig {
  HarvestRunConfig run;  ///< the world (experiment, seed, plants, slope) and the stretch scored (row_length_m)
  SerialBridgeParams bridge;
  std::string manipulator_link, navigation_link;
  double camera_rate_hz = 4.0;    ///< frames per simulated second
  double real_time_factor = 0.0;  ///< the simulation runs at most this fast (0: as fast as lockstep lets it)
  /// Lockstep: after each telemetry frame the simulation waits (up to lockstep_timeout_s of wall time) for the rover
  /// node's drive command, and after each camera frame for perception's `bolls` of that frame, so that the stack's
  /// reaction times do not stretch in simulated time when the simulation runs faster than real time.
  bool lockstep = true;
  double lockstep_timeout_s = 0.1;         ///< wall time, per telemetry frame
  double camera_lockstep_timeout_s = 2.0;  ///< wall time, per camera frame
  double io_period_s = 0.01;               ///< the serial links are served and /clock published this often (simulated)
  double time_limit_s = 900.0;             ///< simulated time after the machine started
  double start_timeout_s = 120.0;          ///< wall time to wait for the harvest machine to start
  std::string metrics_csv, run_name, camera_frame;
  /// false: no harvest machine is waited for or scored; the simulation runs until shut down or time_limit_s (a
  /// rover driven by cmd_vel or a position target, e.g. launch/rover_localization.launch).
  bool harvest = true;
  SensorTopicsConfig sensors;  ///< the localisation sensors' topics (rover_sensor_topics.h)
};

SimNodeConfig readConfig(thorvald_common::ParamReader& r) {
  SimNodeConfig c;
  const std::string experiment = r.choice("experiment", "potted", {"potted", "field"});
  const int seed = r.integer("seed", 1, 0, 1000000);
  c.run = experiment == "field" ? fieldConfig(static_cast<unsigned>(seed)) : pottedConfig(static_cast<unsigned>(seed));
  c.run.sim.realism = *thorvald_sim::realismFromName(r.choice("realism", "ideal", {"ideal", "datasheet"}));
  c.run.sim.row.plants = r.integer("plants", c.run.sim.row.plants, 1, 60);
  c.run.sim.row.bolls_per_plant = r.integer("bolls_per_plant", c.run.sim.row.bolls_per_plant, 0, 10);
  c.run.sim.row.slope_deg = r.number("slope_deg", c.run.sim.row.slope_deg, ParamRange::closed(-15.0, 15.0), "deg");
  c.run.machine.row_length_m =
      r.number("row_length_m", c.run.machine.row_length_m, ParamRange::aboveUpTo(0.0, 100.0), "m");
  c.manipulator_link = r.text("manipulator_port", "/tmp/cotton_harvester_mujoco/manipulator");
  c.navigation_link = r.text("navigation_port", "/tmp/cotton_harvester_mujoco/navigation");
  c.camera_rate_hz = r.number("camera_rate_hz", c.camera_rate_hz, ParamRange::aboveUpTo(0.0, 30.0), "Hz");
  c.real_time_factor = r.number("real_time_factor", c.real_time_factor, ParamRange::closed(0.0, 100.0));
  c.lockstep = r.flag("lockstep", c.lockstep);
  c.lockstep_timeout_s = r.number("lockstep_timeout_s", c.lockstep_timeout_s, ParamRange::aboveUpTo(0.0, 10.0), "s");
  c.camera_lockstep_timeout_s =
      r.number("camera_lockstep_timeout_s", c.camera_lockstep_timeout_s, ParamRange::aboveUpTo(0.0, 30.0), "s");
  c.time_limit_s = r.number("time_limit_s", c.time_limit_s, ParamRange::aboveUpTo(0.0, 36000.0), "s");
  c.start_timeout_s = r.number("start_timeout_s", c.start_timeout_s, ParamRange::aboveUpTo(0.0, 3600.0), "s");
  c.bridge.calibration = simArmCalibration(c.run.sim.geometry);
  c.bridge.pot_noise_counts =
      r.number("pot_noise_counts", c.bridge.pot_noise_counts, ParamRange::closed(0.0, 20.0), "counts");
  c.bridge.seed = static_cast<unsigned>(seed);
  c.metrics_csv = r.text("metrics_csv", "");
  c.run_name = r.text("run_name", "mujoco_rover_sim");
  c.camera_frame = r.text("camera_frame", "camera");
  c.harvest = r.flag("harvest", c.harvest);
  c.sensors = readSensorTopicsConfig(r, static_cast<unsigned>(seed));
  return c;
}

class MujocoRoverSimNode {
 public:
  MujocoRoverSimNode(ros::NodeHandle& nh, const SimNodeConfig& config)
      : config_(config),
        sim_(config.run.sim),
        devices_(sim_, config.bridge, config.manipulator_link, config.navigation_link),
        scorer_(reachableBolls(sim_, config.run.machine.row_length_m), sim_.roverPosition()),
        sensors_(nh, sim_, config.sensors) {
    ROS_INFO("mujoco_rover_sim: manipulation controller on %s, navigation controller on %s",
             config_.manipulator_link.c_str(), config_.navigation_link.c_str());
    clock_pub_ = nh.advertise<rosgraph_msgs::Clock>("/clock", 10);
    image_pub_ = nh.advertise<sensor_msgs::Image>("camera/color/image_raw", 2);
    cloud_pub_ = nh.advertise<sensor_msgs::PointCloud2>("camera/depth/points", 2);
    info_pub_ = nh.advertise<sensor_msgs::CameraInfo>("camera/color/camera_info", 2);
    metrics_pub_ = nh.advertise<diagnostic_msgs::DiagnosticStatus>("harvest/metrics", 1, true);
    status_sub_ = nh.subscribe("harvest/machine_status", 100, &MujocoRoverSimNode::onStatus, this);
    stack_metrics_sub_ = nh.subscribe("harvest/stack_metrics", 10, &MujocoRoverSimNode::onStackMetrics, this);
    if (config_.lockstep) bolls_sub_ = nh.subscribe("bolls", 5, &MujocoRoverSimNode::onBolls, this);
  }

  /// Runs until the harvest machine's run ended or the time limit; then scores. Returns the exit code.
  int run() {
    const auto wall_start = std::chrono::steady_clock::now();
    const double sim_start = sim_.time();
    const double camera_period = 1.0 / config_.camera_rate_hz;
    const double drive_lockstep_s = config_.lockstep ? config_.lockstep_timeout_s : 0.0;
    double next_frame = sim_.time();
    while (ros::ok()) {
      ros::spinOnce();
      devices_.serveLinks();
      const auto frames = advance();
      rosgraph_msgs::Clock clock;
      clock.clock = now();
      clock_pub_.publish(clock);
      devices_.send(frames, drive_lockstep_s, [] { return ros::ok(); });
      if (sim_.time() + 1e-9 >= next_frame) {
        next_frame += camera_period;
        if (publishCamera() && config_.lockstep) awaitPerception();
      }
      if (!config_.harvest) {
        if (sim_.time() - sim_start >= config_.time_limit_s) break;
        pace(wall_start, sim_.time() - sim_start);
        continue;
      }
      const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
      const StackRunState state = stack_.check(sim_.time(), waited, config_.time_limit_s, config_.start_timeout_s);
      if (state == StackRunState::kEnded) break;
      if (state == StackRunState::kNoStart) {
        ROS_FATAL("mujoco_rover_sim: the harvest machine did not start within %.0f s", config_.start_timeout_s);
        return 1;
      }
      pace(wall_start, sim_.time() - sim_start);
    }
    if (!ros::ok() || !config_.harvest) return 0;
    SimRunFigures figures;
    figures.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    figures.sim_s = sim_.time() - sim_start;
    figures.frames = frames_;
    figures.serial_rejected_bytes = devices_.rejectedBytes();
    figures.lockstep_timeouts = devices_.lockstepTimeouts();
    figures.camera_lockstep_timeouts = camera_lockstep_timeouts_;
    report(scorer_.score(stack_.figures(), truthOf(sim_)), figures);
    return 0;
  }

 private:
  /// One I/O period of physics; while anyone listens to the sensors, one step at a time with the sensors sampled
  /// after each (the IMUs' 120 Hz is finer than the I/O period).
  RoverSerialBridge::Output advance() {
    const double step = config_.run.sim.timestep_s;
    if (!sensors_.wanted()) return devices_.advance(config_.io_period_s, step);
    RoverSerialBridge::Output all;
    const long steps = std::max(1L, std::lround(config_.io_period_s / step));
    for (long i = 0; i < steps; ++i) {
      const auto out = devices_.advance(step, step);
      all.manipulator.insert(all.manipulator.end(), out.manipulator.begin(), out.manipulator.end());
      all.navigation.insert(all.navigation.end(), out.navigation.begin(), out.navigation.end());
      sensors_.afterStep();
    }
    return all;
  }

  /// Spins until perception published the bolls of the last camera frame (or the timeout: a frame it rejects).
  void awaitPerception() {
    const auto deadline =
        std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                               std::chrono::duration<double>(config_.camera_lockstep_timeout_s));
    while (ros::ok() && last_bolls_stamp_ < last_frame_stamp_) {
      if (std::chrono::steady_clock::now() >= deadline) {
        ++camera_lockstep_timeouts_;
        return;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
      ros::spinOnce();
    }
  }

  void onBolls(const cotton_harvester::BollArray::ConstPtr& msg) {
    last_bolls_stamp_ = std::max(last_bolls_stamp_, msg->header.stamp);
  }

  /// ROS time of the simulation (1 s after its start: ROS reads a zero time as "no time yet").
  ros::Time now() const { return ros::Time(1.0 + sim_.time()); }

  /// Keeps the simulation at most real_time_factor times as fast as the wall clock.
  void pace(std::chrono::steady_clock::time_point wall_start, double sim_elapsed_s) const {
    if (config_.real_time_factor <= 0.0) return;
    const auto due = wall_start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                      std::chrono::duration<double>(sim_elapsed_s / config_.real_time_factor));
    if (due > std::chrono::steady_clock::now()) std::this_thread::sleep_until(due);
  }

  /// Renders and publishes a camera frame; false when nobody listens (nothing rendered).
  bool publishCamera() {
    if (image_pub_.getNumSubscribers() == 0 && cloud_pub_.getNumSubscribers() == 0) return false;
    cv::Mat bgr, cloud;
    sim_.renderCamera(&bgr, &cloud);
    ++frames_;
    std_msgs::Header header;
    header.stamp = now();
    header.frame_id = config_.camera_frame;
    header.seq = static_cast<std::uint32_t>(frames_);
    const CameraMessages messages = cameraMessages(bgr, cloud, config_.run.sim, header);
    image_pub_.publish(messages.image);
    cloud_pub_.publish(messages.cloud);
    info_pub_.publish(messages.info);
    last_frame_stamp_ = header.stamp;
    return true;
  }

  void onStatus(const thorvald_state_machine::MachineStatus::ConstPtr& msg) {
    if (stack_.onStatus(msg->running, sim_.time()))
      ROS_INFO("mujoco_rover_sim: the harvest machine started at %.2f s", sim_.time());
  }

  void onStackMetrics(const diagnostic_msgs::DiagnosticStatus::ConstPtr& msg) {
    std::vector<std::pair<std::string, std::string>> values;
    for (const auto& kv : msg->values) values.emplace_back(kv.key, kv.value);
    stack_.onMetrics(msg->message, values);
  }

  /// Publishes the run's figures on harvest/metrics, logs them and appends the CSV row.
  void report(const HarvestScore& score, const SimRunFigures& run) {
    diagnostic_msgs::DiagnosticStatus s;
    s.name = "harvest: " + config_.run_name;
    s.level =
        score.outcome == "finished" ? diagnostic_msgs::DiagnosticStatus::OK : diagnostic_msgs::DiagnosticStatus::WARN;
    s.message = score.outcome;
    const auto add = [&s](const std::string& key, double value) { addMetric(&s, key, value); };
    addRunMetrics(&s, score.counts, score.metrics, score.reachable, score.machine_picked, run.sim_s, run.wall_s,
                  run.frames);
    add("reachable_picked", score.reachable_picked);
    add("distance_m", score.counts.distance_m);
    add("serial_rejected_bytes", static_cast<double>(run.serial_rejected_bytes));
    add("lockstep_timeouts", run.lockstep_timeouts);
    add("camera_lockstep_timeouts", run.camera_lockstep_timeouts);
    add("ee_fallback_frames", score.ee_fallback_frames);  // the machine's frames with the arm's calibrated position
    add("frames_without_end_effector", score.frames_without_end_effector);
    metrics_pub_.publish(s);
    ROS_INFO("%s", summaryLine("mujoco_rover_sim", score, run).c_str());
    // Each boll the vacuum did not take, for comparing runs boll by boll (harvest_bench --verbose lists its own).
    for (const std::string& line : missedBollLines("mujoco_rover_sim", score)) ROS_INFO("%s", line.c_str());
    std::string error;
    if (!config_.metrics_csv.empty() &&
        !control::appendCsv(config_.metrics_csv, config_.run_name, score.counts, score.metrics, &error))
      ROS_ERROR("mujoco_rover_sim: %s", error.c_str());
    // Let the latched metrics reach their subscribers before the launch ends (wall time: /clock stops with us).
    ros::WallDuration(0.5).sleep();
  }

  SimNodeConfig config_;
  RoverSim sim_;
  RoverDeviceEmulator devices_;
  HarvestScorer scorer_;
  StackRunReport stack_;
  RoverSensorTopics sensors_;
  ros::Publisher clock_pub_, image_pub_, cloud_pub_, info_pub_, metrics_pub_;
  ros::Subscriber status_sub_, stack_metrics_sub_, bolls_sub_;
  ros::Time last_frame_stamp_, last_bolls_stamp_;
  int camera_lockstep_timeouts_ = 0;
  int frames_ = 0;
};

}  // namespace
}  // namespace sim
}  // namespace cotton_harvester

int main(int argc, char** argv) {
  ros::init(argc, argv, "mujoco_rover_sim");
  ros::NodeHandle nh, pnh("~");
  cotton_harvester::sim::SimNodeConfig config;
  try {
    thorvald_common::ParamReader reader(pnh);
    config = cotton_harvester::sim::readConfig(reader);
    reader.finish();
  } catch (const thorvald_common::ParamError& e) {
    ROS_FATAL("%s", e.what());
    return 1;
  }
  try {
    cotton_harvester::sim::MujocoRoverSimNode node(nh, config);
    return node.run();
  } catch (const std::exception& e) {
    ROS_FATAL("mujoco_rover_sim cannot run: %s", e.what());
    return 1;
  }
}
