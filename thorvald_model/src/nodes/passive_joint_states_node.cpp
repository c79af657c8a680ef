// passive_joint_states: publishes the joints of casters and passive wheels (which nothing drives or measures), and
// every other movable joint of the robot's robot_description that base_driver does not publish (e.g. free-turning
// wheels of a URDF extras fragment), at a fixed position on joint_states, so robot_state_publisher has a complete
// tree next to base_driver's joints.

#include <ros/ros.h>
#include <sensor_msgs/JointState.h>

#include "thorvald_base/robot_config.h"
#include "thorvald_model/model_builder.h"
#include "thorvald_common/ros/param_reader.h"
#include "thorvald_base/ros/robot_config_params.h"

int main(int argc, char** argv) {
  ros::init(argc, argv, "passive_joint_states");
  ros::NodeHandle nh, pnh("~");
  std::vector<std::string> names;
  double rate = 10.0;
  try {
    thorvald_common::ParamReader params(pnh);
    std::string tf_prefix = params.text("tf_prefix", "");
    rate = params.number("rate", 10.0, thorvald_common::ParamRange::aboveUpTo(0.0, 1000.0), "Hz");
    const auto config = thorvald_base::robotConfigFromParams(nh, params.text("robot_file", ""));
    for (const auto& w : config.warnings) ROS_WARN_STREAM(w);
    params.finish();
    if (tf_prefix.empty()) {
      std::string key;
      if (nh.searchParam("tf_prefix", key)) nh.getParam(key, tf_prefix);
    }
    while (!tf_prefix.empty() && tf_prefix.front() == '/') tf_prefix.erase(0, 1);
    // The extras' movable joints come from the robot_description of this namespace when there is one.
    std::string description;
    nh.getParam("robot_description", description);
    const size_t passive = thorvald_model::passiveJointNames(config, tf_prefix).size();
    names = thorvald_model::unpublishedJointNames(config, tf_prefix, description);
    for (size_t i = passive; i < names.size(); ++i)
      ROS_INFO("passive_joint_states: %s (robot_description) is published at 0: nothing measures it", names[i].c_str());
  } catch (const std::exception& e) {
    ROS_FATAL("passive_joint_states cannot start: %s", e.what());
    return 1;
  }
  if (names.empty()) {
    ROS_INFO("passive_joint_states: this robot has no casters or passive wheels, nothing to publish");
    ros::spin();
    return 0;
  }
  ros::Publisher pub = nh.advertise<sensor_msgs::JointState>("joint_states", 10);
  sensor_msgs::JointState msg;
  msg.name = names;
  msg.position.assign(names.size(), 0.0);
  msg.velocity.assign(names.size(), 0.0);
  ros::Timer timer = nh.createTimer(ros::Duration(1.0 / rate), [&](const ros::TimerEvent&) {
    msg.header.stamp = ros::Time::now();
    pub.publish(msg);
  });
  ros::spin();
  return 0;
}
