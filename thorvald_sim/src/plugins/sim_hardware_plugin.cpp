// thorvald_sim/SimHardware: base_driver's BaseHardware plugin for a robot whose joints MuJoCo moves. Each drive's
// command goes to thorvald_sim on `sim/joint_commands`; thorvald_sim answers on `sim/joint_measured` with the
// joints' measured positions and velocities, which the drives report quantised like their encoders. Topics are in
// base_driver's namespace (the robot's). Each relay board of the robot file (`io`) is a SimIoBoard: base_driver
// switches and confirms it as on the real robot (io/<board>/out<k>, .../state, state_unknown, 'io boards'
// diagnostics) and its relays' real state is published as truth on `sim/io/<board>` (std_msgs/UInt8, bit k = output
// k, latched), for scorers only. No CAN bus: relay frames are refused.
#include <pluginlib/class_list_macros.hpp>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <std_msgs/UInt8.h>
#include <thorvald_base/base_hardware.h>
#include <thorvald_common/ros/param_reader.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "thorvald_sim/physics_drive.h"
#include "thorvald_sim/sim_io_board.h"

namespace thorvald_sim {

namespace {

// A PhysicsDrive that sends its command to the simulator every cycle.
class SimJointDrive : public PhysicsDrive {
 public:
  SimJointDrive(const thorvald_base::DriveConfig& config, double timeout_s, ros::Publisher pub,
                const std::string& steering_joint, const std::string& wheel_joint)
      : PhysicsDrive(config, timeout_s), pub_(std::move(pub)), steering_(steering_joint), wheel_(wheel_joint) {}

  void update(double now_s) override {
    PhysicsDrive::update(now_s);
    sensor_msgs::JointState js;
    js.header.stamp = ros::Time(now_s);
    if (config().steered()) {
      js.name.push_back(steering_);
      js.position.push_back(command().steering_rad);
      js.velocity.push_back(0.0);
    }
    js.name.push_back(wheel_);
    js.position.push_back(0.0);
    js.velocity.push_back(command().wheel_speed_radps);
    pub_.publish(js);
  }

 private:
  ros::Publisher pub_;
  std::string steering_, wheel_;
};

}  // namespace

class SimHardware : public thorvald_base::BaseHardware {
 public:
  void readParameters(thorvald_common::ParamReader& params) override {
    timeout_s_ = params.number("sim_joint_timeout", 0.5, thorvald_common::ParamRange::aboveUpTo(0.0, 10.0), "s");
    startup_s_ = params.number("sim_startup_timeout", 60.0, thorvald_common::ParamRange::closed(0.0, 600.0), "s");
    using thorvald_common::ParamRange;
    io_.echo_delay_s = params.number("sim_io_echo_delay", 0.02, ParamRange::closed(0.0, 1.0), "s");
    io_.silent_after_s = params.number("sim_io_silent_after", -1.0, ParamRange::closed(-1.0, 1e6), "s");
    io_.stuck_after_s = params.number("sim_io_stuck_after", -1.0, ParamRange::closed(-1.0, 1e6), "s");
  }

  void initialize(const thorvald_base::RobotConfig& config, const std::string&, const std::string&) override {
    ros::NodeHandle pnh("~");
    nh_.setCallbackQueue(&queue_);
    // The joint names carry the robot's tf prefix, found as base_driver finds it (its reader has checked the type).
    std::string prefix;
    pnh.getParam("tf_prefix", prefix);
    if (prefix.empty()) {
      std::string key;
      if (nh_.searchParam("tf_prefix", key)) nh_.getParam(key, prefix);
    }
    while (!prefix.empty() && prefix.front() == '/') prefix.erase(0, 1);
    const std::string p = prefix.empty() ? "" : prefix + "/";
    const double timeout = timeout_s_, startup = startup_s_;
    pub_ = nh_.advertise<sensor_msgs::JointState>("sim/joint_commands", 20);
    for (const auto& d : config.drives) {
      const std::string steering = p + "steering" + std::to_string(d.index),
                        wheel = p + "wheel" + std::to_string(d.index);
      auto drive = std::make_unique<SimJointDrive>(d, timeout, pub_, steering, wheel);
      joints_[wheel] = {drives_.size(), true};
      if (d.steered()) joints_[steering] = {drives_.size(), false};
      raw_.push_back(drive.get());
      drives_.push_back(std::move(drive));
    }
    for (const auto& io : config.io) addIoBoard(io);
    measured_.assign(raw_.size(), false);
    sub_ = nh_.subscribe("sim/joint_measured", 5, &SimHardware::onMeasured, this);
    // base_driver latches a stop on a drive that is offline: wait for the simulator's first measurement.
    const ros::WallTime deadline = ros::WallTime::now() + ros::WallDuration(startup);
    while (ros::ok() && !allMeasured() && ros::WallTime::now() < deadline)
      queue_.callAvailable(ros::WallDuration(0.05));
    if (!allMeasured())
      throw std::runtime_error("thorvald_sim/SimHardware: no joint measurements on " + sub_.getTopic() + " within " +
                               std::to_string(startup) + " s (~sim_startup_timeout): is thorvald_sim running with " +
                               "this robot's encoders: physics?");
    ROS_INFO_STREAM("SimHardware: " << raw_.size() << " drives moved by thorvald_sim's physics (" << pub_.getTopic()
                                    << " -> " << sub_.getTopic() << ")");
  }

  std::vector<std::unique_ptr<thorvald_base::MotorDrive>> takeDrives() override { return std::move(drives_); }
  std::vector<std::unique_ptr<thorvald_base::Battery>> takeBatteries() override { return {}; }
  std::vector<std::unique_ptr<thorvald_base::IoBoard>> takeIoBoards() override { return std::move(boards_); }
  void poll(double) override { queue_.callAvailable(); }
  std::vector<thorvald_base::CanFrameData> takeRelayFrames() override { return {}; }
  bool sendRelayFrame(const thorvald_base::CanFrameData&, std::string* why) override {
    if (why) *why = "no CAN bus: the base is simulated by thorvald_sim";
    return false;
  }
  std::vector<std::pair<std::string, std::string>> diagnostics() const override {
    return {{"hardware", "thorvald_sim physics (SimHardware)"},
            {"joint measurements received", std::to_string(messages_)},
            {"rejected measurements", std::to_string(rejected_)},
            {"simulated relay boards", std::to_string(board_count_)}};
  }
  bool busOk() const override {
    for (const auto* d : raw_)
      if (!d->status().online) return false;
    return true;
  }

 private:
  double timeout_s_ = 0.5, startup_s_ = 60.0;
  SimIoBoardSettings io_;
  std::vector<std::unique_ptr<thorvald_base::IoBoard>> boards_;  ///< owned by base_driver after takeIoBoards
  size_t board_count_ = 0;
  struct JointOf {
    size_t drive;
    bool wheel;
  };

  void addIoBoard(const thorvald_base::IoConfig& io) {
    auto board = std::make_unique<SimIoBoard>(io, io_);
    ros::Publisher truth = nh_.advertise<std_msgs::UInt8>("sim/io/" + io.name, 1, true);
    board->on_outputs = [truth](uint8_t outputs) {
      std_msgs::UInt8 msg;
      msg.data = outputs;
      truth.publish(msg);
    };
    boards_.push_back(std::move(board));
    ++board_count_;
  }

  bool allMeasured() const {
    for (bool m : measured_)
      if (!m) return false;
    return true;
  }

  void onMeasured(const sensor_msgs::JointState::ConstPtr& msg) {
    ++messages_;
    std::vector<JointMeasurement> m(raw_.size());
    std::vector<int> seen(raw_.size(), 0);
    for (size_t i = 0; i < msg->name.size(); ++i) {
      const auto it = joints_.find(msg->name[i]);
      if (it == joints_.end() || i >= msg->position.size() || i >= msg->velocity.size()) continue;
      auto& jm = m[it->second.drive];
      if (it->second.wheel)
        jm.wheel_position_rad = msg->position[i], jm.wheel_speed_radps = msg->velocity[i];
      else
        jm.steering_rad = msg->position[i], jm.steering_speed_radps = msg->velocity[i];
      seen[it->second.drive] |= it->second.wheel ? 1 : 2;
    }
    for (size_t d = 0; d < raw_.size(); ++d) {
      const int need = raw_[d]->config().steered() ? 3 : 1;
      if (seen[d] != need) continue;  // a drive whose joints are not all in the message keeps its last reading
      if (raw_[d]->measure(m[d], msg->header.stamp.toSec()))
        measured_[d] = true;
      else
        ++rejected_;
    }
  }

  ros::NodeHandle nh_;
  ros::CallbackQueue queue_;
  ros::Publisher pub_;
  ros::Subscriber sub_;
  std::vector<std::unique_ptr<thorvald_base::MotorDrive>> drives_;
  std::vector<SimJointDrive*> raw_;  ///< owned by base_driver after takeDrives
  std::vector<bool> measured_;
  std::map<std::string, JointOf> joints_;
  unsigned long messages_ = 0, rejected_ = 0;
};

}  // namespace thorvald_sim

PLUGINLIB_EXPORT_CLASS(thorvald_sim::SimHardware, thorvald_base::BaseHardware)
