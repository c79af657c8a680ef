// Node `twist_mux`: selects which velocity command reaches the base (see README.md).
#include <exception>

#include <ros/ros.h>
#include <thorvald_common/ros/run_node.h>

#include "mux_node.h"

int main(int argc, char** argv) {
  // SIGINT and SIGTERM stop the node in order, within a second in every state (runNode's StopSignals).
  return thorvald_common::runNode(argc, argv, "twist_mux", [](ros::NodeHandle& nh, ros::NodeHandle& pnh) {
    thorvald_common::ParamReader params(pnh);
    auto node = std::make_shared<thorvald_twist_mux::MuxNode>(nh, pnh, params);
    params.finish();  // warns about unread (misspelt) parameters, logs the effective values
    return node;
  });
}
