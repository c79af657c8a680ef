#pragma once

#include <vector>

#include <opencv2/core.hpp>

#include "cotton_harvester/perception/boll_detector.h"

namespace cotton_harvester {
namespace perception {

/// Maps the network's normalised box coordinates back to image pixels:
///   image_x = scale_x * x_normalised + offset_x, image_y = scale_y * y_normalised + offset_y.
/// For a plain resize scale is the image size and offset 0; for padding it is the network input size.
struct NetInputTransform {
  double scale_x = 1.0;   ///< image pixels per unit of normalised network x [px]
  double scale_y = 1.0;   ///< image pixels per unit of normalised network y [px]
  double offset_x = 0.0;  ///< [px]
  double offset_y = 0.0;  ///< [px]
};

/// Thresholds of the decoding step.
struct YoloDecodeParams {
  double confidence_threshold = 0.5;  ///< minimum class score (objectness x class probability) [0, 1]
  double nms_threshold = 0.4;         ///< IoU above which the weaker of two boxes is suppressed [0, 1]
  int class_id = 0;                   ///< class that is a boll; -1: any class
};

/// Decodes the outputs of OpenCV's Darknet "yolo" layers. Each output is a CV_32F matrix with one row per
/// anchor and grid cell: [centre x, centre y, width, height] normalised to the network input, objectness,
/// then one score per class (OpenCV has already applied the sigmoids, the anchors and multiplied the class
/// probabilities by the objectness). Rows whose score for class_id is below the threshold are dropped, the
/// rest go through non-maximum suppression; boxes are clipped to image_size.
std::vector<BollDetection> decodeYoloOutputs(const std::vector<cv::Mat>& outputs, const NetInputTransform& transform,
                                             const cv::Size& image_size, const YoloDecodeParams& params);

}  // namespace perception
}  // namespace cotton_harvester
