#pragma once

#include <string>
#include <vector>

#include <opencv2/dnn.hpp>

#include "cotton_harvester/perception/boll_detector.h"
#include "cotton_harvester/perception/darknet_boll_detector.h"
#include "cotton_harvester/perception/yolo_decoder.h"

namespace cotton_harvester {
namespace perception {

/// One output head of the boll network: its stride [px at the network input] and anchors (width, height) [px].
struct NetworkHead {
  int stride = 8;
  std::vector<cv::Size2d> anchors;
};

/// Configuration of the trained boll network (models/boll_net.onnx, cotton_harvester/training): a small one-stage
/// detector with two classes, 0 boll and 1 end-effector, run through OpenCV's DNN module. The defaults are the
/// shipped model's (models/README.md).
struct NetworkParams {
  std::string model_path;  ///< ONNX file; empty: defaultNetworkModelPath()
  int input_width = 448;   ///< network input [px], a multiple of the largest stride
  int input_height = 256;
  int classes = 2;
  std::vector<NetworkHead> heads{{8, {{14.0, 14.0}, {24.0, 24.0}}}, {16, {{36.0, 36.0}, {64.0, 64.0}}}};
  InputResize resize = InputResize::kLinear;  ///< the paper's Figure 8 experiment: linear, nearest or none
  bool swap_rb = true;                        ///< trained on RGB; camera images arrive as BGR
  YoloDecodeParams decode{0.4, 0.4, 0};       ///< boll class, its score threshold and NMS
};

/// Returns an empty string when valid (the file is not opened here), otherwise what is wrong.
std::string validate(const NetworkParams& params);

/// The shipped model: models/boll_net.onnx of the cotton_harvester package.
std::string defaultNetworkModelPath();

/// The raw head maps of the boll network (1 x anchors*(5+classes) x rows x cols each: tx, ty, tw, th, objectness,
/// class scores; the finest map goes with the first head, heads listed by increasing stride) as the rows
/// decodeYoloOutputs reads: [cx, cy, w, h] normalised to the network input,
/// objectness, objectness x class probability. cx = (col + sigmoid(tx)) * stride, w = anchor * exp(tw).
std::vector<cv::Mat> bollNetRows(const std::vector<cv::Mat>& maps, const NetworkParams& params);

/// The trained boll network through OpenCV DNN (ONNX). Detections whose centre falls on the exclusion mask are
/// dropped. Besides the bolls (decode.class_id) it keeps the last frame's end-effector detections.
class NetworkBollDetector : public BollDetector {
 public:
  /// Throws std::runtime_error naming the file when the model is missing or cannot be loaded or run,
  /// std::invalid_argument on bad parameters.
  explicit NetworkBollDetector(const NetworkParams& params);

  std::vector<BollDetection> detect(const cv::Mat& bgr, const cv::Mat& exclude) override;

  /// Detections of another class (1: end-effector) in the last frame, before NMS with the bolls.
  std::vector<BollDetection> lastDetectionsOf(int class_id, double threshold) const;

  const NetworkParams& params() const { return params_; }

 private:
  NetworkParams params_;
  cv::dnn::Net net_;
  std::vector<std::string> output_names_;
  std::vector<cv::Mat> rows_;
  NetInputTransform transform_;
  cv::Size image_size_;
};

}  // namespace perception
}  // namespace cotton_harvester
