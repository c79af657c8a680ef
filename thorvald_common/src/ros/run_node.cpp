#include "thorvald_common/ros/run_node.h"

#include <ros/init.h>
#include <ros/console.h>
#include <ros/spinner.h>

#include <exception>

#include "thorvald_common/stop_signals.h"

namespace thorvald_common {
namespace {

/// True when the node was asked to stop (a signal, or roscpp shutting down), so an exception is no failure.
bool stopping() { return StopSignals::requested() || !ros::ok(); }

}  // namespace

int runNode(int argc, char** argv, const std::string& name, const NodeFactory& start, const RunNodeOptions& options) {
  ros::init(argc, argv, name, ros::init_options::NoSigintHandler);
  // Created right after ros::init and destroyed last: the stop deadline covers every later step.
  StopSignals stop_signals(ros::requestShutdown, options.stop_grace_s);
  // The handles outlive the node object: destroying the last handle shuts roscpp (and its logging) down.
  ros::NodeHandle nh;
  ros::NodeHandle pnh("~");
  if (!ros::ok()) return 0;  // stopped while waiting for the master
  std::shared_ptr<void> node;
  try {
    node = start(nh, pnh);
  } catch (const std::exception& e) {  // ParamError, a robot file's ConfigError, a port that cannot open, ...
    // Stopped during start-up: roscpp's isShuttingDown() is false again once its shutdown has finished, so the
    // signal itself is what tells.
    if (stopping()) return 0;
    ROS_FATAL("%s cannot start: %s", name.c_str(), e.what());
    return 1;
  }
  if (options.spinner_threads > 0) {
    ros::AsyncSpinner spinner(static_cast<uint32_t>(options.spinner_threads));
    spinner.start();
    ros::waitForShutdown();
    spinner.stop();
  } else {
    ros::spin();
  }
  node.reset();
  return 0;
}

}  // namespace thorvald_common
