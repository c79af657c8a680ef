#include "thorvald_state_machine/ros/status_publisher.h"

namespace thorvald_state_machine {

thorvald_state_machine::MachineStatus toMsg(const StatusSnapshot& status, const ros::Time& stamp) {
  thorvald_state_machine::MachineStatus msg;
  msg.header.stamp = stamp;
  msg.machine = status.machine;
  msg.active_state = status.active_state;
  msg.last_outcome = status.last_outcome;
  msg.running = status.running;
  msg.preempt_requested = status.preempt_requested;
  msg.transitions = status.transitions;
  msg.history.reserve(status.history.size());
  for (const auto& record : status.history) {
    StateTransition transition;
    if (record.stamp_s > 0.0) transition.stamp.fromSec(record.stamp_s);
    transition.state = record.state;
    transition.outcome = record.outcome;
    transition.next = record.next;
    msg.history.push_back(transition);
  }
  return msg;
}

StatusPublisher::StatusPublisher(ros::NodeHandle& nh, StateMachine& machine, const std::string& topic, double period_s)
    : machine_(machine) {
  publisher_ = nh.advertise<thorvald_state_machine::MachineStatus>(topic, 10, true);
  machine_.setClock([] { return ros::Time::now().toSec(); });
  machine_.setObserver([this](const StatusSnapshot& status) { publish(status); });
  if (period_s > 0.0) {
    timer_ = nh.createTimer(ros::Duration(period_s), [this](const ros::TimerEvent&) { publishNow(); });
  }
  publishNow();
}

StatusPublisher::~StatusPublisher() {
  machine_.setObserver(nullptr);
  timer_.stop();
}

void StatusPublisher::publishNow() { publish(machine_.status()); }

void StatusPublisher::publish(const StatusSnapshot& status) {
  std::lock_guard<std::mutex> lock(mutex_);
  publisher_.publish(toMsg(status, ros::Time::now()));
}

}  // namespace thorvald_state_machine
