// Message conversions of ekf_localization and navsat_transform: ROS messages to the fusion library's samples and
// the filter's state to nav_msgs/Odometry.
#pragma once

#include <string>

#include <geometry_msgs/PoseWithCovariance.h>
#include <geometry_msgs/TransformStamped.h>
#include <geometry_msgs/TwistWithCovariance.h>
#include <nav_msgs/Odometry.h>
#include <ros/time.h>
#include <sensor_msgs/Imu.h>

#include "thorvald_navigation/fusion_ekf.h"
#include "thorvald_navigation/fusion_inputs.h"

namespace thorvald_navigation {

PoseSample toPoseSample(const geometry_msgs::PoseWithCovariance& p);
TwistSample toTwistSample(const geometry_msgs::TwistWithCovariance& t);
ImuSample toImuSample(const sensor_msgs::Imu& m);
/// A tf transform as an isometry (its rotation normalised; identity when it has none).
Eigen::Isometry3d toIsometry(const geometry_msgs::Transform& t);
/// The filter's pose (world frame) and twist (base_link) with their covariances.
nav_msgs::Odometry toOdometry(const FusionEkf& ekf, const ros::Time& stamp, const std::string& world_frame,
                              const std::string& base_link_frame);
/// map -> odom from the fused map -> base_link and tf's odom -> base_link.
geometry_msgs::TransformStamped composeMapToOdom(const geometry_msgs::TransformStamped& map_base,
                                                 const geometry_msgs::TransformStamped& odom_base,
                                                 const std::string& odom_frame);

}  // namespace thorvald_navigation
