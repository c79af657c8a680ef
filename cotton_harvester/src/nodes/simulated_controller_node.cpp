// simulated_controller: the rover's two serial controllers (manipulation, navigation) on
// pseudo-terminals, answering like the hardware, plus an optional simulated row of bolls that
// stands in for perception (publishes `bolls` and `end_effector/position` from the simulated state).
#include <sys/stat.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <thread>

#include <geometry_msgs/PointStamped.h>
#include <ros/ros.h>
#include <std_msgs/Float64.h>
#include <std_msgs/Int32.h>

#include "cotton_harvester/BollArray.h"
#include "cotton_harvester/control/serial_port.h"
#include "cotton_harvester/control/simulated_controllers.h"
#include "cotton_harvester/control/virtual_row.h"
#include "../ros/calibration_params.h"
#include "../ros/node_params.h"

namespace cotton_harvester {
namespace control {
namespace {

/// mkdir -p of the folder that holds `path`.
void makeParentDirectory(const std::string& path) {
  for (std::size_t i = path.find('/', 1); i != std::string::npos; i = path.find('/', i + 1)) {
    ::mkdir(path.substr(0, i).c_str(), 0755);
  }
}

class SimulatedControllerNode {
 public:
  SimulatedControllerNode(ros::NodeHandle& nh, ros::NodeHandle& pnh, const NodeParams& params) {
    manipulator_link_ = readString(params, "manipulator_port", "/tmp/cotton_harvester_sim/manipulator");
    navigation_link_ = readString(params, "navigation_port", "/tmp/cotton_harvester_sim/navigation");
    rate_hz_ = readPositive(params, "rate_hz", 500.0);
    calibration_ = loadCalibration(params.sub("calibration"));

    SimulatedNavigationParams nav;
    nav.drive.max_forward_speed_mps = readPositive(params, "max_forward_speed_mps", nav.drive.max_forward_speed_mps);
    nav.drive.max_reverse_speed_mps = readPositive(params, "max_reverse_speed_mps", nav.drive.max_reverse_speed_mps);
    nav.drive.actuator_rate_pwm_per_s =
        readPositive(params, "actuator_rate_pwm_per_s", nav.drive.actuator_rate_pwm_per_s);
    nav.drive.flow_time_constant_s = readDouble(params, "flow_time_constant_s", nav.drive.flow_time_constant_s);
    nav.drive.deadband_low_pwm = readDouble(params, "deadband_low_pwm", nav.drive.deadband_low_pwm);
    nav.drive.deadband_high_pwm = readDouble(params, "deadband_high_pwm", nav.drive.deadband_high_pwm);
    nav.drive.metres_per_pulse = readPositive(params, "metres_per_pulse", nav.drive.metres_per_pulse);
    nav.pot_counts_per_deg = readDouble(params, "pot_counts_per_deg", nav.pot_counts_per_deg);
    nav.pot_noise_counts = readDouble(params, "pot_noise_counts", nav.pot_noise_counts);
    nav.seed = static_cast<unsigned>(readInt(params, "seed", 7, 0));
    if (const char* bad = nav.drive.check(); *bad) throw ParamError(ros::this_node::getName() + ": " + bad);
    navigation_ = std::make_unique<SimulatedNavigationController>(nav);

    SimulatedManipulatorParams arm;
    arm.vertical_steps_per_s = readPositive(params, "vertical_steps_per_s", arm.vertical_steps_per_s);
    arm.horizontal_steps_per_s = readPositive(params, "horizontal_steps_per_s", arm.horizontal_steps_per_s);
    arm.vertical_start_steps = readInt(params, "vertical_start_steps", arm.vertical_start_steps, 0);
    manipulator_ = std::make_unique<SimulatedManipulationController>(arm);

    row_enabled_ = readBool(params, "virtual_row/enabled", true);
    VirtualRowParams row;
    const NodeParams rnh = params.sub("virtual_row");
    row.plants = readInt(rnh, "plants", row.plants, 0);
    row.bolls_per_plant = readInt(rnh, "bolls_per_plant", row.bolls_per_plant, 0);
    row.first_plant_m = readDouble(rnh, "first_plant_m", row.first_plant_m);
    row.plant_spacing_m = readDouble(rnh, "plant_spacing_m", row.plant_spacing_m);
    row.pick_tolerance_m = readPositive(rnh, "pick_tolerance_m", row.pick_tolerance_m);
    row.pick_success_probability = readDouble(rnh, "pick_success_probability", row.pick_success_probability);
    row.seed = static_cast<unsigned>(readInt(rnh, "seed", static_cast<int>(row.seed), 0));
    row_publish_period_s_ = 1.0 / readPositive(rnh, "publish_rate_hz", 10.0);
    fx_ = readPositive(rnh, "fx", 699.936);
    cx_ = readDouble(rnh, "cx", 685.286);
    cy_ = readDouble(rnh, "cy", 361.248);
    row_ = std::make_unique<VirtualRow>(row);

    makeParentDirectory(manipulator_link_);
    makeParentDirectory(navigation_link_);
    if (!openPorts()) throw ParamError(ports_error_);

    bolls_pub_ = nh.advertise<cotton_harvester::BollArray>("bolls", 5);
    effector_pub_ = nh.advertise<geometry_msgs::PointStamped>("end_effector/position", 5);
    truth_pub_ = nh.advertise<std_msgs::Float64>("sim/rover_position", 5);
    remaining_pub_ = nh.advertise<std_msgs::Int32>("sim/bolls_remaining", 1, true);
    vanish_sub_ = pnh.subscribe("vanish", 1, &SimulatedControllerNode::onVanish, this);
    publish_timer_ =
        nh.createWallTimer(ros::WallDuration(row_publish_period_s_), [this](const ros::WallTimerEvent&) { publish(); });
    worker_ = std::thread([this] { loop(); });
  }

  ~SimulatedControllerNode() {
    running_ = false;
    if (worker_.joinable()) worker_.join();
  }

 private:
  bool openPorts() {
    if (!manipulator_pty_.open(manipulator_link_)) {
      ports_error_ = manipulator_pty_.lastError();
      return false;
    }
    if (!navigation_pty_.open(navigation_link_)) {
      ports_error_ = navigation_pty_.lastError();
      manipulator_pty_.close();
      return false;
    }
    ROS_INFO("simulated manipulation controller on %s (%s), navigation controller on %s (%s)",
             manipulator_link_.c_str(), manipulator_pty_.slaveName().c_str(), navigation_link_.c_str(),
             navigation_pty_.slaveName().c_str());
    return true;
  }

  void onVanish(const std_msgs::Float64::ConstPtr& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    ROS_WARN("simulated controllers: serial devices vanish for %.1f s", msg->data);
    manipulator_pty_.close();
    navigation_pty_.close();
    reappear_at_ = std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                          std::chrono::duration<double>(std::max(0.0, msg->data)));
    vanished_ = true;
  }

  void loop() {
    const auto period = std::chrono::duration<double>(1.0 / rate_hz_);
    auto last = std::chrono::steady_clock::now();
    std::uint8_t buffer[512];
    while (running_ && ros::ok()) {
      std::this_thread::sleep_for(period);
      const auto now = std::chrono::steady_clock::now();
      const double dt = std::min(0.05, std::chrono::duration<double>(now - last).count());
      last = now;
      std::lock_guard<std::mutex> lock(mutex_);
      if (vanished_ && now >= reappear_at_) {
        if (openPorts()) {
          vanished_ = false;
        } else {
          ROS_ERROR_THROTTLE(1.0, "simulated controllers cannot reopen: %s", ports_error_.c_str());
        }
      }
      if (!vanished_) {
        long n;
        while ((n = manipulator_pty_.read(buffer, sizeof(buffer))) > 0) {
          const auto reply = manipulator_->receive(buffer, static_cast<std::size_t>(n));
          manipulator_pty_.write(reply.data(), reply.size());
        }
        while ((n = navigation_pty_.read(buffer, sizeof(buffer))) > 0) {
          navigation_->receive(buffer, static_cast<std::size_t>(n));
        }
      }
      // The hardware keeps running while its USB link is gone (the navigation watchdog stops it).
      const auto reports = manipulator_->step(dt);
      const auto telemetry = navigation_->step(dt);
      if (!vanished_) {
        manipulator_pty_.write(reports.data(), reports.size());
        navigation_pty_.write(telemetry.data(), telemetry.size());
      }
      const bool brush = manipulator_->brushOn();
      if (brush && !brush_was_on_ && row_enabled_) {
        const int taken = row_->brush(navigation_->drive().positionM(), endEffector());
        ROS_INFO("simulated brush pass took %d boll(s), %d left", taken, row_->remaining());
      }
      brush_was_on_ = brush;
    }
  }

  Point3 endEffector() const {
    const double extension = calibration_.horizontalExtensionFromSteps(manipulator_->horizontal().positionSteps());
    const double depth = calibration_.verticalDistanceFromSteps(manipulator_->vertical().positionSteps());
    return row_->endEffector(extension, depth);
  }

  void publish() {
    std::lock_guard<std::mutex> lock(mutex_);
    const ros::Time stamp = ros::Time::now();
    std_msgs::Float64 truth;
    truth.data = navigation_->drive().positionM();
    truth_pub_.publish(truth);
    if (!row_enabled_) return;
    std_msgs::Int32 remaining;
    remaining.data = row_->remaining();
    remaining_pub_.publish(remaining);

    cotton_harvester::BollArray bolls;
    bolls.header.stamp = stamp;
    bolls.header.frame_id = "camera";
    bolls.nearest_reachable = -1;
    double nearest = INFINITY;
    for (const auto& sighting : row_->visibleBolls(navigation_->drive().positionM())) {
      cotton_harvester::Boll boll;
      boll.position.x = sighting.position.x;
      boll.position.y = sighting.position.y;
      boll.position.z = sighting.position.z;
      boll.confidence = static_cast<float>(sighting.confidence);
      boll.reachable = sighting.reachable;
      boll.u = static_cast<int>(std::lround(fx_ * sighting.position.x / sighting.position.z + cx_));
      boll.v = static_cast<int>(std::lround(fx_ * sighting.position.y / sighting.position.z + cy_));
      const double distance = std::sqrt(boll.position.x * boll.position.x + boll.position.y * boll.position.y +
                                        boll.position.z * boll.position.z);
      if (boll.reachable && distance < nearest) {
        nearest = distance;
        bolls.nearest_reachable = static_cast<int>(bolls.bolls.size());
      }
      bolls.bolls.push_back(boll);
    }
    bolls_pub_.publish(bolls);
    const Point3 ee = endEffector();
    geometry_msgs::PointStamped effector;
    effector.header = bolls.header;
    effector.point.x = ee.x;
    effector.point.y = ee.y;
    effector.point.z = ee.z;
    effector_pub_.publish(effector);
  }

  std::string manipulator_link_, navigation_link_, ports_error_;
  double rate_hz_ = 500.0;
  double row_publish_period_s_ = 0.1;
  double fx_ = 699.936, cx_ = 685.286, cy_ = 361.248;
  bool row_enabled_ = true;
  ManipulatorCalibration calibration_;
  std::unique_ptr<SimulatedNavigationController> navigation_;
  std::unique_ptr<SimulatedManipulationController> manipulator_;
  std::unique_ptr<VirtualRow> row_;
  PseudoTerminal manipulator_pty_, navigation_pty_;
  std::mutex mutex_;
  bool vanished_ = false;
  bool brush_was_on_ = false;
  std::chrono::steady_clock::time_point reappear_at_;
  std::atomic<bool> running_{true};
  std::thread worker_;
  ros::Publisher bolls_pub_, effector_pub_, truth_pub_, remaining_pub_;
  ros::Subscriber vanish_sub_;
  ros::WallTimer publish_timer_;
};

}  // namespace
}  // namespace control
}  // namespace cotton_harvester

int main(int argc, char** argv) {
  ros::init(argc, argv, "simulated_controller");
  ros::NodeHandle nh, pnh("~");
  try {
    thorvald_common::ParamReader reader(pnh);
    reader.alsoRead("diagnostic_period");  // diagnostic_updater's own
    cotton_harvester::control::SimulatedControllerNode node(nh, pnh, cotton_harvester::control::NodeParams(reader));
    reader.finish();
    ros::spin();
  } catch (const std::exception& e) {
    ROS_FATAL("simulated_controller cannot start: %s", e.what());
    return 1;
  }
  return 0;
}
