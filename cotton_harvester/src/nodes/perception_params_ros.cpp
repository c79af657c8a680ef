#include "perception_params_ros.h"

#include <cmath>
#include <optional>
#include <sstream>
#include <vector>

#include <thorvald_common/ros/param_reader.h>

namespace cotton_harvester {
namespace {

using namespace perception;

/// The node's reads through the workspace's ParamReader (typed, unread parameters warned about by finish()); the
/// ranges and the relations between parameters are the libraries' validate() functions below.
class Reader {
 public:
  explicit Reader(const ros::NodeHandle& pnh) : r_(pnh, "harvest_perception") {}

  void read(const std::string& key, double* value, const char*) {
    *value = r_.number(key, *value, thorvald_common::ParamRange::any());
  }
  void read(const std::string& key, int* value, const char*) { *value = r_.integer(key, *value); }
  void read(const std::string& key, bool* value, const char*) { *value = r_.flag(key, *value); }
  void read(const std::string& key, std::string* value, const char*) { *value = r_.text(key, *value); }
  /// An image direction [du, dv].
  void read(const std::string& key, cv::Point2d* value, const char*) {
    const std::vector<double> v = r_.numbers(key, {value->x, value->y}, thorvald_common::ParamRange::any(), "", 2, 2);
    *value = {v[0], v[1]};
  }

  /// A string parameter that must be one of a parser's names.
  template <typename E, typename Parse>
  void readChoice(const std::string& key, E* value, Parse parse, const char* expected) {
    if (!r_.has(key)) return;
    const std::string name = r_.text(key, "");
    const auto parsed = parse(name);
    if (!parsed)
      throw thorvald_common::ParamError("harvest_perception: ~" + key + ": expected " + expected + " (got '" + name +
                                        "')");
    *value = *parsed;
  }

  void finish() { r_.finish(); }

 private:
  thorvald_common::ParamReader r_;
};

void readCamera(Reader& r, PerceptionNodeConfig* config) {
  CameraIntrinsics& k = config->pipeline.intrinsics;
  r.read("camera/fx", &k.fx, "a positive number [px]");
  r.read("camera/fy", &k.fy, "a positive number [px]");
  r.read("camera/cx", &k.cx, "a number [px]");
  r.read("camera/cy", &k.cy, "a number [px]");
  r.read("camera/width", &k.width, "an integer [px]");
  r.read("camera/height", &k.height, "an integer [px]");
  r.read("use_camera_info", &config->use_camera_info, "true or false");
}

std::optional<EndEffectorPoint> parseEndEffectorPoint(const std::string& name) {
  if (name == "centroid") return EndEffectorPoint::kCentroid;
  if (name == "tip") return EndEffectorPoint::kTip;
  return std::nullopt;
}

void readEndEffector(Reader& r, EndEffectorParams* e) {
  r.readChoice("end_effector/colour_space", &e->colour_space, parseEndEffectorColourSpace, "'hsv' or 'rgb'");
  r.read("end_effector/hue_min", &e->hue_min, "an integer in [0, 179]");
  r.read("end_effector/hue_max", &e->hue_max, "an integer in [0, 179]");
  r.read("end_effector/saturation_min", &e->saturation_min, "an integer in [0, 255]");
  r.read("end_effector/value_min", &e->value_min, "an integer in [0, 255]");
  r.read("end_effector/glare_value_min", &e->glare_value_min, "an integer in [0, 255]");
  r.read("end_effector/glare_saturation_min", &e->glare_saturation_min, "an integer in [0, 255]");
  r.read("end_effector/arm_base_offset_m", &e->arm_base_offset_m, "a number in [0, 10) [m]");
  r.read("end_effector/arm_depth_tolerance_m", &e->arm_depth_tolerance_m, "a number in (0, 1) [m]");
  r.read("end_effector/r_min", &e->r_min, "an integer in [0, 255]");
  r.read("end_effector/r_max", &e->r_max, "an integer in [0, 255]");
  r.read("end_effector/g_min", &e->g_min, "an integer in [0, 255]");
  r.read("end_effector/g_max", &e->g_max, "an integer in [0, 255]");
  r.read("end_effector/b_min", &e->b_min, "an integer in [0, 255]");
  r.read("end_effector/b_max", &e->b_max, "an integer in [0, 255]");
  r.read("end_effector/min_area_px", &e->min_area_px, "an integer >= 1 [px]");
  r.read("end_effector/opening_px", &e->opening_px, "an integer >= 0 [px]");
  r.readChoice("end_effector/point", &e->point, parseEndEffectorPoint, "'centroid' or 'tip'");
  r.read("end_effector/tip_direction", &e->tip_direction, "a list [du, dv]");
  r.read("end_effector/arm_direction", &e->arm_direction, "a list [du, dv] ([0, 0]: no arm mask)");
}

void readColour(Reader& r, ColourBollParams* c) {
  r.read("colour/value_min", &c->value_min, "an integer in [0, 255]");
  r.read("colour/saturation_max", &c->saturation_max, "an integer in [0, 255]");
  r.read("colour/opening_fraction", &c->opening_fraction, "a number in [0, 2]");
  r.read("colour/min_visible_fraction", &c->min_visible_fraction, "a number in (0, 1]");
  r.read("colour/max_cluster_bolls", &c->max_cluster_bolls, "an integer in [1, 100]");
  r.read("colour/split_neck_ratio", &c->split_neck_ratio, "a number in [0, 1]");
  r.read("colour/min_circularity", &c->min_circularity, "a number in [0, 1]");
  r.read("colour/min_solidity", &c->min_solidity, "a number in [0, 1]");
  r.read("colour/max_aspect_ratio", &c->max_aspect_ratio, "a number >= 1");
  r.read("colour/partial_min_fraction", &c->partial_min_fraction, "a number in [0, 1] (0: no partial bolls)");
}

void readDarknet(Reader& r, PerceptionNodeConfig* config) {
  DarknetParams& d = config->darknet;
  r.read("darknet/cfg", &d.cfg_path, "a path to a Darknet .cfg file");
  r.read("darknet/weights", &d.weights_path, "a path to a Darknet .weights file");
  r.read("darknet/input_width", &d.input_width, "a positive multiple of 32 [px]");
  r.read("darknet/input_height", &d.input_height, "a positive multiple of 32 [px]");
  r.read("darknet/confidence_threshold", &d.decode.confidence_threshold, "a number in [0, 1]");
  r.read("darknet/nms_threshold", &d.decode.nms_threshold, "a number in [0, 1]");
  r.read("darknet/class_id", &d.decode.class_id, "an integer >= -1");
  r.read("darknet/swap_rb", &d.swap_rb, "true or false");
  r.readChoice("darknet/resize", &d.resize, parseInputResize, "'linear', 'nearest' or 'none'");
  config->use_darknet = !d.cfg_path.empty() || !d.weights_path.empty();
}

/// `detector` and the trained network's settings (network/*).
void readNetwork(Reader& r, PerceptionNodeConfig* config) {
  std::string detector = "auto";
  r.read("detector", &detector, "'auto', 'colour', 'darknet' or 'network'");
  NetworkParams& n = config->network;
  r.read("network/model", &n.model_path, "a path to an ONNX file (empty: the shipped models/boll_net.onnx)");
  r.read("network/confidence_threshold", &n.decode.confidence_threshold, "a number in [0, 1]");
  r.read("network/nms_threshold", &n.decode.nms_threshold, "a number in [0, 1]");
  r.readChoice("network/resize", &n.resize, parseInputResize, "'linear', 'nearest' or 'none'");
  if (n.model_path.empty()) n.model_path = defaultNetworkModelPath();
  if (detector == "network") {
    config->use_network = true;
    config->use_darknet = false;
  } else if (detector == "colour") {
    config->use_darknet = false;
  } else if (detector == "darknet") {
    config->use_darknet = true;
  } else if (detector != "auto") {
    config->detector_error = "~detector: expected 'auto', 'colour', 'darknet' or 'network' (got '" + detector + "'); ";
  }
}

/// Where a detection is in 3D and whether it is taken: depth, boll geometry, plausibility, reach, the nearest.
void readLocation(Reader& r, PerceptionParams* p) {
  r.read("depth/window_px", &p->locator.window_px, "an odd integer >= 1 [px]");
  r.read("depth/min_valid_points", &p->locator.min_valid_points, "an integer >= 1");
  r.readChoice("depth/model", &p->locator.depth_model, parseDepthModel, "'ray' or 'paper'");

  r.read("geometry/camera_height_m", &p->geometry.camera_height_m, "a number in (0, 20) [m]");
  r.read("geometry/boll_radius_min_m", &p->geometry.boll_radius_min_m, "a number > 0 [m]");
  r.read("geometry/boll_radius_max_m", &p->geometry.boll_radius_max_m, "a number >= boll_radius_min_m [m]");
  r.read("geometry/boll_height_min_m", &p->geometry.boll_height_min_m, "a number >= 0 [m]");
  r.read("geometry/boll_height_max_m", &p->geometry.boll_height_max_m, "a number >= boll_height_min_m [m]");
  r.read("geometry/boll_radius_typical_m", &p->geometry.boll_radius_typical_m, "a number in [min, max] radius [m]");
  r.read("size_fallback", &p->size_fallback, "true or false");

  r.read("check_plausibility", &p->check_plausibility, "true or false");
  r.read("boll_min_dome_fraction", &p->boll_min_dome_fraction, "a number in [0, 1] (0: no dome test)");
  r.read("boll_dome_sigmas", &p->boll_dome_sigmas, "a number >= 0");

  r.read("reach/max_depth_m", &p->reach.max_depth_m, "a positive number [m]");
  r.read("reach/horizontal_arm_length_m", &p->reach.horizontal_arm_length_m, "a number >= 0 [m]");
  r.read("reach/arm_origin_x_m", &p->reach.arm_origin_x_m, "a number [m]");
  r.readChoice("nearest_by", &p->nearest_by, parseNearestBy, "'camera' or 'end_effector'");
}

/// The node's own settings: image and cloud pairing, the debug image, the arm's prior.
void readNodeSettings(Reader& r, PerceptionNodeConfig* config) {
  r.read("max_stamp_diff_s", &config->max_stamp_diff_s, "a number >= 0 [s]");
  r.read("publish_debug_image", &config->publish_debug_image, "true or false");
  r.read("arm_prior/enabled", &config->arm_prior, "true or false");
  r.read("arm_prior/extension_zero_x_m", &config->arm_extension_zero_x_m, "a number [m]");
  r.read("arm_prior/radius_m", &config->arm_prior_radius_m, "a positive number [m]");
  r.read("arm_prior/housing_half_m", &config->arm_housing_half_m, "a positive number [m]");
  r.read("arm_prior/max_age_s", &config->arm_prior_max_age_s, "a positive number [s]");
}

/// Every bad value of the configuration, each with its key (empty when it is usable).
std::string validate(const PerceptionNodeConfig& config) {
  std::string errors;
  const std::string pipeline_errors = validate(config.pipeline);
  if (!pipeline_errors.empty()) errors += pipeline_errors;
  const std::string colour_errors = validate(config.colour);
  if (!colour_errors.empty()) errors += "colour: " + colour_errors;
  if (config.use_darknet) {
    const std::string darknet_errors = validate(config.darknet);
    if (!darknet_errors.empty()) errors += "darknet: " + darknet_errors;
  }
  errors += config.detector_error;
  if (config.use_network) {
    const std::string network_errors = validate(config.network);
    if (!network_errors.empty()) errors += "network: " + network_errors;
  }
  if (!(config.max_stamp_diff_s >= 0.0) || !std::isfinite(config.max_stamp_diff_s))
    errors += "~max_stamp_diff_s: expected a number >= 0; ";
  if (!std::isfinite(config.arm_extension_zero_x_m)) errors += "~arm_prior/extension_zero_x_m: expected a number; ";
  if (!(config.arm_prior_radius_m > 0.0) || !std::isfinite(config.arm_prior_radius_m))
    errors += "~arm_prior/radius_m: expected a number > 0; ";
  if (!(config.arm_housing_half_m > 0.0) || !std::isfinite(config.arm_housing_half_m))
    errors += "~arm_prior/housing_half_m: expected a number > 0; ";
  if (!(config.arm_prior_max_age_s > 0.0) || !std::isfinite(config.arm_prior_max_age_s))
    errors += "~arm_prior/max_age_s: expected a number > 0; ";
  return errors;
}

/// Reads and validates; a parameter of the wrong type throws thorvald_common::ParamError.
bool loadPerceptionNodeConfigOrThrow(const ros::NodeHandle& pnh, PerceptionNodeConfig* config, std::string* error) {
  Reader r(pnh);
  readCamera(r, config);
  readEndEffector(r, &config->pipeline.end_effector);
  readColour(r, &config->colour);
  readDarknet(r, config);
  readNetwork(r, config);
  readLocation(r, &config->pipeline);
  readNodeSettings(r, config);
  r.finish();
  *error = validate(*config);
  return error->empty();
}

}  // namespace

bool loadPerceptionNodeConfig(const ros::NodeHandle& pnh, PerceptionNodeConfig* config, std::string* error) {
  try {
    return loadPerceptionNodeConfigOrThrow(pnh, config, error);
  } catch (const thorvald_common::ParamError& e) {
    *error = e.what();
    return false;
  }
}

}  // namespace cotton_harvester
