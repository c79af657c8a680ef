#pragma once

// ROS adapter of the state-machine library (library thorvald_state_machine_ros); the core
// headers next to this folder know nothing of ROS.

#include <mutex>
#include <string>

#include <ros/ros.h>

#include "thorvald_state_machine/MachineStatus.h"
#include "thorvald_state_machine/status_snapshot.h"
#include "thorvald_state_machine/state_machine.h"

namespace thorvald_state_machine {

/// Converts a status snapshot to its message (header stamped with `stamp`).
MachineStatus toMsg(const StatusSnapshot& status, const ros::Time& stamp);

/// Publishes a machine's status on `topic` (latched) on every transition and every `period_s`
/// seconds, and stamps the machine's history with ROS time (simulated time when /clock runs).
/// The machine must outlive the publisher; the publisher installs itself as the machine's observer.
class StatusPublisher {
 public:
  StatusPublisher(ros::NodeHandle& nh, StateMachine& machine, const std::string& topic = "machine_status",
                  double period_s = 1.0);
  ~StatusPublisher();
  StatusPublisher(const StatusPublisher&) = delete;
  StatusPublisher& operator=(const StatusPublisher&) = delete;

  /// Publishes the current status now.
  void publishNow();

 private:
  void publish(const StatusSnapshot& status);

  StateMachine& machine_;
  ros::Publisher publisher_;
  ros::Timer timer_;
  std::mutex mutex_;
};

}  // namespace thorvald_state_machine
