// bumper: the front safety bumper latches a safety stop that only a person clears. While latched it holds its
// lock engaged (published at a fixed rate, so a mux lock with a timeout engages if this node dies); the
// ~reset service clears it, and refuses while the bumper is still pressed.
#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/ros.h>
#include <std_msgs/Bool.h>
#include <std_srvs/Trigger.h>
#include <thorvald_common/ros/param_reader.h>
#include <thorvald_common/ros/run_node.h>

#include <mutex>

namespace {

class Bumper {
 public:
  Bumper(ros::NodeHandle& nh, ros::NodeHandle& pnh) {
    thorvald_common::ParamReader params(pnh);
    const double rate = params.number("publish_rate", 20.0, thorvald_common::ParamRange::aboveUpTo(0.0, 200.0), "Hz");
    input_timeout_s_ = params.number("input_timeout", 0.0, thorvald_common::ParamRange::atLeast(0.0), "s");
    const std::string lock_topic = params.text("lock_topic", "bumper/lock");
    latched_ = params.flag("start_latched", false);
    params.alsoRead("diagnostic_period");
    params.finish();
    if (latched_) reason_ = "started latched: a person must clear it";
    sub_ = nh.subscribe("bumper", 5, &Bumper::onBumper, this);
    lock_pub_ = nh.advertise<std_msgs::Bool>(lock_topic, 1, true);
    reset_srv_ = pnh.advertiseService("reset", &Bumper::onReset, this);
    diagnostics_.setHardwareID("front bumper");
    diagnostics_.add("bumper", this, &Bumper::diagnose);
    last_input_ = ros::Time::now();
    timer_ = nh.createTimer(ros::Duration(1.0 / rate), [this](const ros::TimerEvent&) { publish(); });
  }

 private:
  void onBumper(const std_msgs::Bool& m) {
    std::lock_guard<std::mutex> l(mutex_);
    last_input_ = ros::Time::now();
    pressed_ = m.data;
    if (pressed_ && !latched_) {
      latched_ = true;
      reason_ = "bumper pressed";
      ++presses_;
      ROS_ERROR("bumper: pressed, safety stop latched until a person calls %s", reset_srv_.getService().c_str());
    }
  }

  bool onReset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& res) {
    std::lock_guard<std::mutex> l(mutex_);
    if (pressed_) {
      res.success = false;
      res.message = "the bumper is still pressed";
    } else if (inputLost()) {
      res.success = false;
      res.message = "no bumper input for more than input_timeout";
    } else {
      res.success = true;
      res.message = latched_ ? "safety stop cleared" : "no safety stop was latched";
      if (latched_) ROS_WARN("bumper: safety stop cleared by a person");
      latched_ = false;
      reason_.clear();
    }
    return true;
  }

  bool inputLost() const {
    return input_timeout_s_ > 0.0 && (ros::Time::now() - last_input_).toSec() > input_timeout_s_;
  }

  void publish() {
    std_msgs::Bool lock;
    {
      std::lock_guard<std::mutex> l(mutex_);
      if (!latched_ && inputLost()) {
        latched_ = true;
        reason_ = "bumper input lost";
        ROS_ERROR("bumper: no input for %.2f s: safety stop latched", input_timeout_s_);
      }
      lock.data = latched_;
    }
    lock_pub_.publish(lock);
    diagnostics_.update();
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& stat) {
    std::lock_guard<std::mutex> l(mutex_);
    if (latched_)
      stat.summary(diagnostic_msgs::DiagnosticStatus::ERROR, "safety stop latched: " + reason_);
    else
      stat.summary(diagnostic_msgs::DiagnosticStatus::OK, "released");
    stat.add("pressed", pressed_);
    stat.add("presses", presses_);
  }

  std::mutex mutex_;
  bool pressed_ = false, latched_ = false;
  int presses_ = 0;
  double input_timeout_s_ = 0.0;
  std::string reason_;
  ros::Time last_input_;
  ros::Subscriber sub_;
  ros::Publisher lock_pub_;
  ros::ServiceServer reset_srv_;
  ros::Timer timer_;
  diagnostic_updater::Updater diagnostics_;
};

}  // namespace

int main(int argc, char** argv) {
  thorvald_common::RunNodeOptions options;
  options.spinner_threads = 1;
  return thorvald_common::runNode<Bumper>(argc, argv, "bumper", options);
}
