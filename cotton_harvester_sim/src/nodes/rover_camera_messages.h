#pragma once
// The simulated downward camera's frames as the ZED driver publishes them (ROS adapter of mujoco_rover_sim).

#include <opencv2/core.hpp>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Header.h>

#include "cotton_harvester_sim/rover_sim.h"

namespace cotton_harvester {
namespace sim {

struct CameraMessages {
  sensor_msgs::Image image;        ///< bgr8
  sensor_msgs::PointCloud2 cloud;  ///< organised, x y z float32, NaN where no depth
  sensor_msgs::CameraInfo info;    ///< the pinhole of RoverSimParams, no distortion
};

/// bgr: CV_8UC3; cloud: CV_32FC3 of the same size (camera frame [m]); both stamped with `header`.
CameraMessages cameraMessages(const cv::Mat& bgr, const cv::Mat& cloud, const RoverSimParams& p,
                              const std_msgs::Header& header);

}  // namespace sim
}  // namespace cotton_harvester
