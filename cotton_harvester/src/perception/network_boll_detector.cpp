#include "cotton_harvester/perception/network_boll_detector.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace cotton_harvester {
namespace perception {

#ifndef COTTON_HARVESTER_MODELS_DIR
#define COTTON_HARVESTER_MODELS_DIR "models"
#endif

std::string defaultNetworkModelPath() { return std::string(COTTON_HARVESTER_MODELS_DIR) + "/boll_net.onnx"; }

std::string validate(const NetworkParams& p) {
  std::ostringstream error;
  if (p.heads.empty()) error << "heads must name at least one output head; ";
  int largest_stride = 1;
  for (const NetworkHead& head : p.heads) {
    if (head.stride < 1 || head.anchors.empty()) error << "each head needs a stride >= 1 and anchors; ";
    for (const cv::Size2d& a : head.anchors)
      if (!(a.width > 0.0 && a.height > 0.0)) error << "anchors must be positive; ";
    if (head.stride < largest_stride) error << "heads must be listed by increasing stride; ";
    largest_stride = std::max(largest_stride, head.stride);
  }
  if (p.input_width < largest_stride || p.input_width % largest_stride != 0)
    error << "input_width must be a positive multiple of " << largest_stride << " (got " << p.input_width << "); ";
  if (p.input_height < largest_stride || p.input_height % largest_stride != 0)
    error << "input_height must be a positive multiple of " << largest_stride << " (got " << p.input_height << "); ";
  if (p.classes < 1) error << "classes must be >= 1 (got " << p.classes << "); ";
  if (!(p.decode.confidence_threshold >= 0.0 && p.decode.confidence_threshold <= 1.0))
    error << "confidence_threshold must be in [0, 1] (got " << p.decode.confidence_threshold << "); ";
  if (!(p.decode.nms_threshold >= 0.0 && p.decode.nms_threshold <= 1.0))
    error << "nms_threshold must be in [0, 1] (got " << p.decode.nms_threshold << "); ";
  if (p.decode.class_id < -1 || p.decode.class_id >= p.classes)
    error << "class_id must be in [-1, classes) (got " << p.decode.class_id << "); ";
  return error.str();
}

namespace {

float sigmoid(float x) { return 1.0f / (1.0f + std::exp(-x)); }

/// One head's raw map as decoder rows (see bollNetRows); empty when the map's shape does not fit the head.
cv::Mat headRows(const cv::Mat& map, const NetworkHead& head, const NetworkParams& p) {
  const int anchors = static_cast<int>(head.anchors.size()), fields = 5 + p.classes;
  if (map.dims != 4 || map.type() != CV_32F || map.size[1] != anchors * fields) return {};
  const int rows = map.size[2], cols = map.size[3], plane = rows * cols;
  cv::Mat out(anchors * plane, fields, CV_32F);
  const float* data = map.ptr<float>();
  for (int a = 0; a < anchors; ++a) {
    const float* base = data + static_cast<size_t>(a) * fields * plane;
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) {
        const int cell = r * cols + c;
        float* row = out.ptr<float>(a * plane + cell);
        row[0] = (c + sigmoid(base[cell])) * head.stride / p.input_width;
        row[1] = (r + sigmoid(base[plane + cell])) * head.stride / p.input_height;
        row[2] = static_cast<float>(head.anchors[a].width * std::exp(std::min(base[2 * plane + cell], 6.0f)) /
                                    p.input_width);
        row[3] = static_cast<float>(head.anchors[a].height * std::exp(std::min(base[3 * plane + cell], 6.0f)) /
                                    p.input_height);
        row[4] = sigmoid(base[4 * plane + cell]);
        for (int k = 0; k < p.classes; ++k) row[5 + k] = row[4] * sigmoid(base[(5 + k) * plane + cell]);
      }
  }
  return out;
}

}  // namespace

std::vector<cv::Mat> bollNetRows(const std::vector<cv::Mat>& maps, const NetworkParams& params) {
  // The finest map belongs to the smallest stride, whatever order the network gives them in.
  std::vector<const cv::Mat*> ordered;
  for (const cv::Mat& map : maps) ordered.push_back(&map);
  const auto cells = [](const cv::Mat* m) { return m->dims == 4 ? m->size[2] * m->size[3] : 0; };
  std::stable_sort(ordered.begin(), ordered.end(),
                   [&](const cv::Mat* a, const cv::Mat* b) { return cells(a) > cells(b); });
  std::vector<cv::Mat> rows;
  for (size_t h = 0; h < ordered.size() && h < params.heads.size(); ++h) {
    cv::Mat head = headRows(*ordered[h], params.heads[h], params);
    if (!head.empty()) rows.push_back(head);
  }
  return rows;
}

NetworkBollDetector::NetworkBollDetector(const NetworkParams& params) : params_(params) {
  if (params_.model_path.empty()) params_.model_path = defaultNetworkModelPath();
  const std::string error = validate(params_);
  if (!error.empty()) throw std::invalid_argument("network detector parameters: " + error);
  const std::string& path = params_.model_path;
  if (!std::ifstream(path).good()) throw std::runtime_error("network detector: cannot open model '" + path + "'");
  try {
    net_ = cv::dnn::readNetFromONNX(path);
  } catch (const cv::Exception& e) {
    throw std::runtime_error("network detector: cannot load model '" + path + "': " + e.what());
  }
  if (net_.empty()) throw std::runtime_error("network detector: model '" + path + "' gives an empty network");
  net_.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  net_.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  output_names_ = net_.getUnconnectedOutLayersNames();
  // One pass on a grey frame: a model of another shape fails here, naming the file, not on the first camera frame.
  std::vector<cv::Mat> maps;
  try {
    const cv::Size input(params_.input_width, params_.input_height);
    net_.setInput(netInputBlob(cv::Mat(input, CV_8UC3, cv::Scalar::all(127)), input, params_.resize, false));
    net_.forward(maps, output_names_);
  } catch (const cv::Exception& e) {
    throw std::runtime_error("network detector: model '" + path + "' does not run: " + e.what());
  }
  if (bollNetRows(maps, params_).size() != params_.heads.size())
    throw std::runtime_error("network detector: model '" + path + "' has outputs of another shape than its " +
                             std::to_string(params_.heads.size()) + " heads of " + std::to_string(params_.classes) +
                             " classes");
}

std::vector<BollDetection> NetworkBollDetector::detect(const cv::Mat& bgr, const cv::Mat& exclude) {
  rows_.clear();
  if (bgr.empty() || bgr.type() != CV_8UC3) return {};
  const cv::Size input(params_.input_width, params_.input_height);
  net_.setInput(netInputBlob(bgr, input, params_.resize, params_.swap_rb));
  std::vector<cv::Mat> maps;
  net_.forward(maps, output_names_);
  rows_ = bollNetRows(maps, params_);
  transform_ = inputTransform(bgr.size(), input, params_.resize);
  image_size_ = bgr.size();
  std::vector<BollDetection> bolls = decodeYoloOutputs(rows_, transform_, image_size_, params_.decode);
  if (exclude.size() != bgr.size()) return bolls;
  return withoutExcluded(std::move(bolls), exclude);
}

std::vector<BollDetection> NetworkBollDetector::lastDetectionsOf(int class_id, double threshold) const {
  YoloDecodeParams decode = params_.decode;
  decode.class_id = class_id;
  decode.confidence_threshold = threshold;
  return decodeYoloOutputs(rows_, transform_, image_size_, decode);
}

}  // namespace perception
}  // namespace cotton_harvester
