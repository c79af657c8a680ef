#include "cotton_harvester/perception/darknet_boll_detector.h"

#include <fstream>
#include <sstream>
#include <stdexcept>

#include <opencv2/imgproc.hpp>

namespace cotton_harvester {
namespace perception {

std::optional<InputResize> parseInputResize(const std::string& name) {
  if (name == "linear") return InputResize::kLinear;
  if (name == "nearest") return InputResize::kNearest;
  if (name == "none") return InputResize::kNone;
  return std::nullopt;
}

std::string toString(InputResize resize) {
  switch (resize) {
    case InputResize::kLinear:
      return "linear";
    case InputResize::kNearest:
      return "nearest";
    case InputResize::kNone:
      return "none";
  }
  return "?";
}

std::string validate(const DarknetParams& p) {
  std::ostringstream error;
  if (p.cfg_path.empty()) error << "cfg_path must name a Darknet .cfg file; ";
  if (p.weights_path.empty()) error << "weights_path must name a Darknet .weights file; ";
  if (p.input_width < 32 || p.input_width % 32 != 0)
    error << "input_width must be a positive multiple of 32 (got " << p.input_width << "); ";
  if (p.input_height < 32 || p.input_height % 32 != 0)
    error << "input_height must be a positive multiple of 32 (got " << p.input_height << "); ";
  if (!(p.decode.confidence_threshold >= 0.0 && p.decode.confidence_threshold <= 1.0))
    error << "confidence_threshold must be in [0, 1] (got " << p.decode.confidence_threshold << "); ";
  if (!(p.decode.nms_threshold >= 0.0 && p.decode.nms_threshold <= 1.0))
    error << "nms_threshold must be in [0, 1] (got " << p.decode.nms_threshold << "); ";
  if (p.decode.class_id < -1) error << "class_id must be >= -1 (got " << p.decode.class_id << "); ";
  return error.str();
}

NetInputTransform inputTransform(const cv::Size& image_size, const DarknetParams& params) {
  return inputTransform(image_size, cv::Size(params.input_width, params.input_height), params.resize);
}

NetInputTransform inputTransform(const cv::Size& image_size, const cv::Size& input_size, InputResize resize) {
  NetInputTransform transform;
  if (resize == InputResize::kNone) {
    // Image pixels keep their size: a normalised unit spans the whole network input.
    transform.scale_x = input_size.width;
    transform.scale_y = input_size.height;
  } else {
    transform.scale_x = image_size.width;
    transform.scale_y = image_size.height;
  }
  return transform;
}

cv::Mat netInputBlob(const cv::Mat& bgr, const cv::Size& input_size, InputResize resize, bool swap_rb) {
  cv::Mat sized;
  if (resize == InputResize::kNone) {
    // Darknet pads with mid grey; the image keeps its pixels (cropped where larger than the input).
    sized = cv::Mat(input_size, CV_8UC3, cv::Scalar(127, 127, 127));
    const cv::Rect region(0, 0, std::min(bgr.cols, input_size.width), std::min(bgr.rows, input_size.height));
    bgr(region).copyTo(sized(region));
  } else {
    const int interpolation = resize == InputResize::kNearest ? cv::INTER_NEAREST : cv::INTER_LINEAR;
    cv::resize(bgr, sized, input_size, 0.0, 0.0, interpolation);
  }
  return cv::dnn::blobFromImage(sized, 1.0 / 255.0, input_size, cv::Scalar(), swap_rb, false);
}

std::vector<BollDetection> withoutExcluded(std::vector<BollDetection> bolls, const cv::Mat& exclude) {
  if (exclude.empty() || exclude.type() != CV_8U) return bolls;
  std::vector<BollDetection> kept;
  for (const BollDetection& boll : bolls) {
    const cv::Point p(static_cast<int>(boll.centroid.x), static_cast<int>(boll.centroid.y));
    if (p.x < 0 || p.y < 0 || p.x >= exclude.cols || p.y >= exclude.rows || exclude.at<uint8_t>(p) == 0)
      kept.push_back(boll);
  }
  return kept;
}

DarknetBollDetector::DarknetBollDetector(const DarknetParams& params) : params_(params) {
  const std::string error = validate(params);
  if (!error.empty()) throw std::invalid_argument("darknet detector parameters: " + error);
  for (const std::string& path : {params.cfg_path, params.weights_path}) {
    if (!std::ifstream(path).good()) throw std::runtime_error("darknet detector: cannot open '" + path + "'");
  }
  try {
    net_ = cv::dnn::readNetFromDarknet(params.cfg_path, params.weights_path);
  } catch (const cv::Exception& e) {
    throw std::runtime_error("darknet detector: cannot load '" + params.cfg_path + "' with '" + params.weights_path +
                             "': " + e.what());
  }
  if (net_.empty()) throw std::runtime_error("darknet detector: '" + params.cfg_path + "' gives an empty network");
  net_.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  net_.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  output_names_ = net_.getUnconnectedOutLayersNames();
}

std::vector<BollDetection> DarknetBollDetector::detect(const cv::Mat& bgr, const cv::Mat& exclude) {
  outputs_.clear();
  if (bgr.empty() || bgr.type() != CV_8UC3) return {};
  const cv::Size input_size(params_.input_width, params_.input_height);
  net_.setInput(netInputBlob(bgr, input_size, params_.resize, params_.swap_rb));
  net_.forward(outputs_, output_names_);
  std::vector<BollDetection> bolls =
      decodeYoloOutputs(outputs_, inputTransform(bgr.size(), params_), bgr.size(), params_.decode);
  if (exclude.size() != bgr.size()) return bolls;
  return withoutExcluded(std::move(bolls), exclude);
}

}  // namespace perception
}  // namespace cotton_harvester
