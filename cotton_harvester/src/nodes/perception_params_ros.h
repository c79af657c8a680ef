#pragma once

#include <string>

#include <ros/node_handle.h>

#include "cotton_harvester/perception/colour_boll_detector.h"
#include "cotton_harvester/perception/darknet_boll_detector.h"
#include "cotton_harvester/perception/network_boll_detector.h"
#include "cotton_harvester/perception/perception_pipeline.h"

namespace cotton_harvester {

/// Everything harvest_perception reads from its private namespace.
struct PerceptionNodeConfig {
  perception::PerceptionParams pipeline;
  perception::ColourBollParams colour;
  perception::DarknetParams darknet;
  bool use_darknet = false;  ///< true when darknet/cfg is set
  perception::NetworkParams network;
  /// `detector: network`: the trained boll network (network/model, default the shipped models/boll_net.onnx).
  /// `colour` or `darknet` choose those; `auto` (default): darknet when darknet/cfg is set, else colour.
  bool use_network = false;
  std::string detector_error;      ///< a `detector` value that names no detector
  bool use_camera_info = false;    ///< take the intrinsics from camera_info instead of camera/*
  double max_stamp_diff_s = 0.05;  ///< image and cloud stamps further apart are not paired [s]
  bool publish_debug_image = true;
  /// The end-effector searched for only near where the arm's own sensing puts it (manipulator/joint_states:
  /// `horizontal` extension, `vertical` distance of the housing's top face from the camera), as
  /// PerceptionPipeline::process with an EndEffectorPrior; false: the whole image.
  bool arm_prior = false;
  double arm_extension_zero_x_m = -0.55;  ///< camera-frame x of the housing's centre at extension 0 [m]
  double arm_prior_radius_m = 0.08;       ///< EndEffectorPrior::radius_m
  double arm_housing_half_m = 0.05;       ///< EndEffectorPrior::housing_half_m
  double arm_prior_max_age_s = 0.5;       ///< joint states further from the image's stamp are not used [s]
};

/// Loads and validates the configuration. On failure returns false and error names every bad key with the
/// value that was expected.
bool loadPerceptionNodeConfig(const ros::NodeHandle& pnh, PerceptionNodeConfig* config, std::string* error);

}  // namespace cotton_harvester
