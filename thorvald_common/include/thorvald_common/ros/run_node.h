#pragma once

#include <ros/node_handle.h>

#include <functional>
#include <memory>
#include <string>

namespace thorvald_common {

/// How runNode spins a node once it is built.
struct RunNodeOptions {
  /// 0: ros::spin() in the main thread; n > 0: an AsyncSpinner with n threads while main waits for shutdown.
  int spinner_threads = 0;
  /// [s] > 0: after SIGINT or SIGTERM the process ends at the latest this long after the signal (StopSignals).
  double stop_grace_s = 0.7;
};

/// Builds a node's object from its public and private handles (reading its parameters on the way); the object
/// lives until the node stops. Throws ParamError (or any std::exception) when the node cannot start.
using NodeFactory = std::function<std::shared_ptr<void>(ros::NodeHandle& nh, ros::NodeHandle& pnh)>;

/// The body of a node's main(), the same in every node of the workspace:
/// - ros::init without roscpp's SIGINT handler, and StopSignals (SIGINT and SIGTERM stop the node in order,
///   within `options.stop_grace_s` in every state, also while waiting for a master that does not answer);
/// - the handles `nh` and `~`, then `start`;
/// - a ParamError or other exception from `start` becomes one ROS_FATAL line "<name> cannot start: <what>" and
///   exit code 1; a stop signal during start-up exits 0;
/// - spins until shutdown, destroys the node object, returns 0.
/// Returns main()'s exit code.
int runNode(int argc, char** argv, const std::string& name, const NodeFactory& start,
            const RunNodeOptions& options = {});

/// runNode for a node class constructed as `Node(nh, pnh)`.
template <class Node>
int runNode(int argc, char** argv, const std::string& name, const RunNodeOptions& options = {}) {
  return runNode(
      argc, argv, name,
      [](ros::NodeHandle& nh, ros::NodeHandle& pnh) -> std::shared_ptr<void> {
        return std::make_shared<Node>(nh, pnh);
      },
      options);
}

}  // namespace thorvald_common
