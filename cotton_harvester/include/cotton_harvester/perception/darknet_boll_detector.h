#pragma once

#include <optional>
#include <string>
#include <vector>

#include <opencv2/dnn.hpp>

#include "cotton_harvester/perception/boll_detector.h"
#include "cotton_harvester/perception/yolo_decoder.h"

namespace cotton_harvester {
namespace perception {

/// How the camera image is brought to the network's input size. The paper (§2.5, Figure 8) found that
/// feeding the image without interpolation detected most bolls.
enum class InputResize {
  kLinear,   ///< bilinear resize to the input size
  kNearest,  ///< nearest-neighbour resize to the input size
  kNone,     ///< no interpolation: the image is placed top-left and padded (grey) up to the input size, or
             ///< cropped where it is larger
};

std::optional<InputResize> parseInputResize(const std::string& name);
std::string toString(InputResize resize);

/// Configuration of the tiny-YOLOv3 detector (paper §2.5).
struct DarknetParams {
  std::string cfg_path;      ///< Darknet network description (.cfg)
  std::string weights_path;  ///< Darknet weights (.weights)
  int input_width = 416;     ///< network input width [px], a multiple of 32
  int input_height = 416;    ///< network input height [px], a multiple of 32
  InputResize resize = InputResize::kLinear;
  bool swap_rb = true;  ///< Darknet networks are trained on RGB; camera images arrive as BGR
  YoloDecodeParams decode;
};

/// Returns an empty string when valid (paths are not opened here), otherwise what is wrong.
std::string validate(const DarknetParams& params);

/// Computes the network input blob layout for an image: how the image is placed and how to map back.
NetInputTransform inputTransform(const cv::Size& image_size, const DarknetParams& params);
/// As above for any network of this input size and resize (DarknetBollDetector, NetworkBollDetector).
NetInputTransform inputTransform(const cv::Size& image_size, const cv::Size& input_size, InputResize resize);

/// The network input blob (1x3xHxW, values / 255) of an 8-bit colour image: resized to input_size, or with kNone
/// placed top-left without interpolation and padded mid grey (cropped where larger).
cv::Mat netInputBlob(const cv::Mat& bgr, const cv::Size& input_size, InputResize resize, bool swap_rb);

/// The detections whose centre is not on the exclusion mask (CV_8U of the image's size; empty: all kept).
std::vector<BollDetection> withoutExcluded(std::vector<BollDetection> bolls, const cv::Mat& exclude);

/// Tiny YOLOv3 through OpenCV's DNN module: loads the Darknet cfg + weights, runs the network on each frame and
/// decodes the yolo layers into bolls. Detections whose centre falls on the exclusion mask are dropped.
class DarknetBollDetector : public BollDetector {
 public:
  /// Throws std::runtime_error naming the file when the network cannot be loaded, std::invalid_argument on
  /// bad parameters.
  explicit DarknetBollDetector(const DarknetParams& params);

  std::vector<BollDetection> detect(const cv::Mat& bgr, const cv::Mat& exclude) override;

  /// Raw outputs of the last forward pass (one matrix per yolo layer), for inspection.
  const std::vector<cv::Mat>& lastOutputs() const { return outputs_; }

 private:
  DarknetParams params_;
  cv::dnn::Net net_;
  std::vector<std::string> output_names_;
  std::vector<cv::Mat> outputs_;
};

}  // namespace perception
}  // namespace cotton_harvester
