#pragma once

#include <string>

#include <ros/node_handle.h>

#include "cotton_harvester/perception/colour_boll_detector.h"
#include "cotton_harvester/perception/darknet_boll_detector.h"
#include "cotton_harvester/perception/perception_pipeline.h"

namespace cotton_harvester {

/// Everything harvest_perception reads from its private namespace.
struct PerceptionNodeConfig {
  perception::PerceptionParams pipeline;
  perception::ColourBollParams colour;
  perception::DarknetParams darknet;
  bool use_darknet = false;        ///< true when darknet/cfg is set
  bool use_camera_info = false;    ///< take the intrinsics from camera_info instead of camera/*
  double max_stamp_diff_s = 0.05;  ///< image and cloud stamps further apart are not paired [s]
  bool publish_debug_image = true;
};

/// Loads and validates the configuration. On failure returns false and error names every bad key with the
/// value that was expected.
bool loadPerceptionNodeConfig(const ros::NodeHandle& pnh, PerceptionNodeConfig* config, std::string* error);

}  // namespace cotton_harvester
