// mujoco_rover_sim: the cotton rover and its row in MuJoCo as the harvest stack's nodes see a real rover. The
// navigation and manipulation controllers answer on pseudo-terminals with the hardware's byte protocols (the `rover`
// and `manipulator` nodes open them as serial devices), the downward camera is published as the ZED driver publishes
// it (colour image, organised cloud, camera info), and the simulated time as /clock. It is also the run's scorer,
// the only node that reads the simulator's truth: when the harvest machine reports that its run ended (or at the time
// limit) it counts the bolls the vacuum took, publishes harvest/metrics, appends the CSV row and exits 0 (1 when the
// world or the ports cannot be made).
#include <sys/stat.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include <diagnostic_msgs/DiagnosticStatus.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Clock.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <thorvald_common/param_reader.h>
#include <thorvald_state_machine/MachineStatus.h>

#include "cotton_harvester/BollArray.h"
#include "cotton_harvester/control/harvest_metrics.h"
#include "cotton_harvester/control/serial_port.h"
#include "cotton_harvester/sim/harvest_run.h"
#include "cotton_harvester/sim/rover_serial_bridge.h"
#include "harvest_metrics_status.h"

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
};

SimNodeConfig readConfig(thorvald_common::ParamReader& r) {
  SimNodeConfig c;
  const std::string experiment = r.choice("experiment", "potted", {"potted", "field"});
  const int seed = r.integer("seed", 1, 0, 1000000);
  c.run = experiment == "field" ? fieldConfig(static_cast<unsigned>(seed)) : pottedConfig(static_cast<unsigned>(seed));
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
  return c;
}

/// mkdir -p of the folder that holds `path`.
void makeParentDirectory(const std::string& path) {
  for (std::size_t i = path.find('/', 1); i != std::string::npos; i = path.find('/', i + 1))
    ::mkdir(path.substr(0, i).c_str(), 0755);
}

/// What the harvest stack tells about its run (its own status and metrics topics; nothing of the truth).
struct StackReport {
  std::mutex mutex;
  bool started = false;                  ///< the machine ran
  double started_at_s = 0.0;             ///< simulated time of its first running status
  std::string outcome;                   ///< set when its metrics say "ended: <outcome>"
  std::map<std::string, double> values;  ///< its last metrics (detected, reached, ...)
};

class MujocoRoverSimNode {
 public:
  MujocoRoverSimNode(ros::NodeHandle& nh, const SimNodeConfig& config)
      : config_(config), sim_(config.run.sim), bridge_(sim_, config.bridge) {
    makeParentDirectory(config_.manipulator_link);
    makeParentDirectory(config_.navigation_link);
    if (!manipulator_pty_.open(config_.manipulator_link)) throw std::runtime_error(manipulator_pty_.lastError());
    if (!navigation_pty_.open(config_.navigation_link)) throw std::runtime_error(navigation_pty_.lastError());
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
    reachable_ = reachableBolls(sim_, config_.run.machine.row_length_m);
    start_position_ = sim_.roverPosition();
  }

  /// Runs until the harvest machine's run ended or the time limit; then scores. Returns the exit code.
  int run() {
    const auto wall_start = std::chrono::steady_clock::now();
    const double sim_start = sim_.time();
    const double camera_period = 1.0 / config_.camera_rate_hz;
    double next_frame = sim_.time();
    std::uint8_t buffer[512];
    while (ros::ok()) {
      ros::spinOnce();
      serveLinks(buffer, sizeof(buffer));
      const auto out = advance(config_.io_period_s);
      if (!out.manipulator.empty()) manipulator_pty_.write(out.manipulator.data(), out.manipulator.size());
      if (!out.navigation.empty()) {
        const std::size_t commands = bridge_.driveCommands();
        navigation_pty_.write(out.navigation.data(), out.navigation.size());
        if (config_.lockstep) awaitDriveCommand(commands, buffer, sizeof(buffer));
      }
      if (sim_.time() + 1e-9 >= next_frame) {
        next_frame += camera_period;
        if (publishCamera() && config_.lockstep) awaitPerception();
      }
      {
        std::lock_guard<std::mutex> lock(stack_.mutex);
        if (!stack_.outcome.empty()) break;
        if (stack_.started && sim_.time() - stack_.started_at_s > config_.time_limit_s) {
          stack_.outcome = "time_limit";
          break;
        }
        const double waited = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
        if (!stack_.started && waited > config_.start_timeout_s) {
          ROS_FATAL("mujoco_rover_sim: the harvest machine did not start within %.0f s", config_.start_timeout_s);
          return 1;
        }
      }
      pace(wall_start, sim_.time() - sim_start);
    }
    if (!ros::ok()) return 0;
    const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    score(wall_s, sim_.time() - sim_start);
    return 0;
  }

 private:
  void serveLinks(std::uint8_t* buffer, std::size_t size) {
    long n;
    while ((n = manipulator_pty_.read(buffer, size)) > 0) {
      const auto reply = bridge_.receiveManipulator(buffer, static_cast<std::size_t>(n));
      if (!reply.empty()) manipulator_pty_.write(reply.data(), reply.size());
    }
    while ((n = navigation_pty_.read(buffer, size)) > 0) bridge_.receiveNavigation(buffer, static_cast<std::size_t>(n));
  }

  /// Serves the links until the rover node answered the telemetry with a drive command (or the timeout).
  void awaitDriveCommand(std::size_t commands_before, std::uint8_t* buffer, std::size_t size) {
    const auto deadline =
        std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                               std::chrono::duration<double>(config_.lockstep_timeout_s));
    while (bridge_.driveCommands() == commands_before && ros::ok()) {
      if (std::chrono::steady_clock::now() >= deadline) {
        ++lockstep_timeouts_;
        return;
      }
      std::this_thread::sleep_for(std::chrono::microseconds(200));
      serveLinks(buffer, size);
    }
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

  RoverSerialBridge::Output advance(double seconds) {
    RoverSerialBridge::Output all;
    const double dt = config_.run.sim.timestep_s;
    const int steps = std::max(1, static_cast<int>(std::lround(seconds / dt)));
    for (int i = 0; i < steps; ++i) {
      auto out = bridge_.advance(dt);
      all.manipulator.insert(all.manipulator.end(), out.manipulator.begin(), out.manipulator.end());
      all.navigation.insert(all.navigation.end(), out.navigation.begin(), out.navigation.end());
    }
    rosgraph_msgs::Clock clock;
    clock.clock = now();
    clock_pub_.publish(clock);
    return all;
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

    sensor_msgs::Image image;
    image.header = header;
    image.height = static_cast<std::uint32_t>(bgr.rows);
    image.width = static_cast<std::uint32_t>(bgr.cols);
    image.encoding = "bgr8";
    image.step = image.width * 3;
    image.data.resize(static_cast<std::size_t>(image.step) * image.height);
    for (int v = 0; v < bgr.rows; ++v) std::memcpy(&image.data[v * image.step], bgr.ptr(v), image.step);

    sensor_msgs::PointCloud2 points;
    points.header = header;
    points.height = static_cast<std::uint32_t>(cloud.rows);
    points.width = static_cast<std::uint32_t>(cloud.cols);
    const char* names[3] = {"x", "y", "z"};
    for (int i = 0; i < 3; ++i) {
      sensor_msgs::PointField f;
      f.name = names[i];
      f.offset = static_cast<std::uint32_t>(4 * i);
      f.datatype = sensor_msgs::PointField::FLOAT32;
      f.count = 1;
      points.fields.push_back(f);
    }
    points.is_bigendian = false;
    points.point_step = 12;
    points.row_step = points.point_step * points.width;
    points.is_dense = false;
    points.data.resize(static_cast<std::size_t>(points.row_step) * points.height);
    for (int v = 0; v < cloud.rows; ++v) std::memcpy(&points.data[v * points.row_step], cloud.ptr(v), points.row_step);

    const RoverSimParams& p = config_.run.sim;
    sensor_msgs::CameraInfo info;
    info.header = header;
    info.width = image.width;
    info.height = image.height;
    info.distortion_model = "plumb_bob";
    info.D.assign(5, 0.0);
    info.K = {p.fx, 0.0, p.cx, 0.0, p.fx, p.cy, 0.0, 0.0, 1.0};
    info.R = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
    info.P = {p.fx, 0.0, p.cx, 0.0, 0.0, p.fx, p.cy, 0.0, 0.0, 0.0, 1.0, 0.0};
    image_pub_.publish(image);
    cloud_pub_.publish(points);
    info_pub_.publish(info);
    last_frame_stamp_ = header.stamp;
    return true;
  }

  void onStatus(const thorvald_state_machine::MachineStatus::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(stack_.mutex);
    if (msg->running && !stack_.started) {
      stack_.started = true;
      stack_.started_at_s = sim_.time();
      ROS_INFO("mujoco_rover_sim: the harvest machine started at %.2f s", sim_.time());
    }
  }

  void onStackMetrics(const diagnostic_msgs::DiagnosticStatus::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(stack_.mutex);
    for (const auto& kv : msg->values) {
      try {
        stack_.values[kv.key] = std::stod(kv.value);
      } catch (const std::exception&) {
        // "n/a" ratios: not needed
      }
    }
    const std::string ended = "ended: ";
    if (stack_.started && msg->message.compare(0, ended.size(), ended) == 0)
      stack_.outcome = msg->message.substr(ended.size());
  }

  /// The run's figures: what the vacuum took (truth) over the time the machine ran, with the stack's own counts of
  /// bolls detected and reached.
  void score(double wall_s, double sim_s) {
    control::HarvestCounts counts;
    std::string outcome;
    {
      std::lock_guard<std::mutex> lock(stack_.mutex);
      outcome = stack_.outcome;
      const auto value = [this](const char* key) {
        const auto it = stack_.values.find(key);
        return it == stack_.values.end() ? 0.0 : it->second;
      };
      counts.detected = static_cast<int>(value("detected"));
      counts.reached = static_cast<int>(value("reached"));
      counts.skipped = static_cast<int>(value("skipped"));
      counts.pick_attempts = static_cast<int>(value("pick_attempts"));
      machine_picked_ = static_cast<int>(value("picked"));
      stack_ee_fallback_ = value("ee_fallback_frames");
      stack_no_effector_ = value("frames_without_end_effector");
      // The machine's own run time (its clock is the simulated /clock); at the time limit, since it started.
      const auto run_time = stack_.values.find("time_s");
      counts.time_s = outcome != "time_limit" && run_time != stack_.values.end()
                          ? run_time->second
                          : sim_.time() - (stack_.started ? stack_.started_at_s : 0.0);
    }
    counts.bolls_present = static_cast<int>(sim_.bolls().size());
    counts.picked = sim_.bollsCaptured();
    counts.distance_m = (sim_.roverPosition() - start_position_).norm();
    const control::HarvestMetrics m = control::computeMetrics(counts);
    int reachable = 0, reachable_picked = 0;
    for (std::size_t i = 0; i < reachable_.size(); ++i) {
      reachable += reachable_[i];
      reachable_picked += reachable_[i] && sim_.bolls()[i].captured;
    }

    diagnostic_msgs::DiagnosticStatus s;
    s.name = "harvest: " + config_.run_name;
    s.level = outcome == "finished" ? diagnostic_msgs::DiagnosticStatus::OK : diagnostic_msgs::DiagnosticStatus::WARN;
    s.message = outcome;
    const auto add = [&s](const std::string& key, double value) { addMetric(&s, key, value); };
    addRunMetrics(&s, counts, m, reachable, machine_picked_, sim_s, wall_s, frames_);
    add("reachable_picked", reachable_picked);
    add("distance_m", counts.distance_m);
    add("serial_rejected_bytes", static_cast<double>(bridge_.rejectedBytes()));
    add("lockstep_timeouts", lockstep_timeouts_);
    add("camera_lockstep_timeouts", camera_lockstep_timeouts_);
    add("ee_fallback_frames", stack_ee_fallback_);  // the machine's frames with the arm's calibrated position
    add("frames_without_end_effector", stack_no_effector_);
    metrics_pub_.publish(s);
    ROS_INFO(
        "mujoco_rover_sim: %s; bolls %d (reachable %d), detected %d, reached %d, picked %d (machine: %d); time %.1f s, "
        "CT %.1f s, ASR %.1f %%, DP %.1f %%, MRR %.1f %%, OV %.2f cm/s; %d frames; %.2fx real time; lockstep timeouts: "
        "%d drive, %d camera; end effector from calibration %.0f, missing %.0f",
        outcome.c_str(), counts.bolls_present, reachable, counts.detected, counts.reached, counts.picked,
        machine_picked_, counts.time_s, m.cycle_time_s.value_or(0.0), m.action_success_pct.value_or(0.0),
        m.detection_performance_pct.value_or(0.0), m.reaching_ratio_pct.value_or(0.0), m.operation_velocity_cm_s,
        frames_, wall_s > 0.0 ? sim_s / wall_s : 0.0, lockstep_timeouts_, camera_lockstep_timeouts_, stack_ee_fallback_,
        stack_no_effector_);
    // Each boll the vacuum did not take, for comparing runs boll by boll (harvest_bench --verbose lists its own).
    for (std::size_t i = 0; i < sim_.bolls().size(); ++i) {
      const BollTruth& b = sim_.bolls()[i];
      if (b.captured) continue;
      ROS_INFO("mujoco_rover_sim: missed boll %zu (plant %d, x %.2f y %.2f z %.2f)%s; nozzle closest %.1f cm", i,
               b.plant, b.centre.x(), b.centre.y(), b.centre.z(),
               i < reachable_.size() && reachable_[i] ? "" : " unreachable",
               std::isfinite(b.closest_vacuum_m) ? 100.0 * b.closest_vacuum_m : -1.0);
    }
    std::string error;
    if (!config_.metrics_csv.empty() && !control::appendCsv(config_.metrics_csv, config_.run_name, counts, m, &error))
      ROS_ERROR("mujoco_rover_sim: %s", error.c_str());
    // Let the latched metrics reach their subscribers before the launch ends (wall time: /clock stops with us).
    ros::WallDuration(0.5).sleep();
  }

  SimNodeConfig config_;
  RoverSim sim_;
  RoverSerialBridge bridge_;
  control::PseudoTerminal manipulator_pty_, navigation_pty_;
  ros::Publisher clock_pub_, image_pub_, cloud_pub_, info_pub_, metrics_pub_;
  ros::Subscriber status_sub_, stack_metrics_sub_, bolls_sub_;
  ros::Time last_frame_stamp_, last_bolls_stamp_;
  int lockstep_timeouts_ = 0, camera_lockstep_timeouts_ = 0;
  StackReport stack_;
  std::vector<bool> reachable_;
  Eigen::Vector3d start_position_ = Eigen::Vector3d::Zero();
  int frames_ = 0;
  int machine_picked_ = 0;
  double stack_ee_fallback_ = 0.0, stack_no_effector_ = 0.0;  ///< the machine's end-effector counts
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
