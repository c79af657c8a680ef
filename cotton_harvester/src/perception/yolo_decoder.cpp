#include "cotton_harvester/perception/yolo_decoder.h"

#include <cmath>

#include <opencv2/dnn.hpp>

namespace cotton_harvester {
namespace perception {

std::vector<BollDetection> decodeYoloOutputs(const std::vector<cv::Mat>& outputs, const NetInputTransform& transform,
                                             const cv::Size& image_size, const YoloDecodeParams& params) {
  std::vector<cv::Rect2d> boxes;
  std::vector<float> scores;
  const cv::Rect2d image_rect(0.0, 0.0, image_size.width, image_size.height);
  for (const cv::Mat& output : outputs) {
    if (output.empty() || output.type() != CV_32F || output.dims != 2 || output.cols < 6) continue;
    const int classes = output.cols - 5;
    if (params.class_id >= classes) continue;
    for (int row = 0; row < output.rows; ++row) {
      const float* values = output.ptr<float>(row);
      float score = 0.0f;
      if (params.class_id >= 0) {
        score = values[5 + params.class_id];
      } else {
        for (int c = 0; c < classes; ++c) score = std::max(score, values[5 + c]);
      }
      if (!std::isfinite(score) || score < params.confidence_threshold) continue;
      const double cx = transform.scale_x * values[0] + transform.offset_x;
      const double cy = transform.scale_y * values[1] + transform.offset_y;
      const double w = transform.scale_x * values[2];
      const double h = transform.scale_y * values[3];
      if (!std::isfinite(cx) || !std::isfinite(cy) || !std::isfinite(w) || !std::isfinite(h)) continue;
      const cv::Rect2d box = cv::Rect2d(cx - 0.5 * w, cy - 0.5 * h, w, h) & image_rect;
      if (box.area() <= 0.0) continue;
      boxes.push_back(box);
      scores.push_back(score);
    }
  }

  std::vector<int> kept;
  cv::dnn::NMSBoxes(boxes, scores, static_cast<float>(params.confidence_threshold),
                    static_cast<float>(params.nms_threshold), kept);
  std::vector<BollDetection> bolls;
  bolls.reserve(kept.size());
  for (int index : kept) {
    BollDetection boll;
    boll.box = boxes[index];
    boll.centroid = {boxes[index].x + 0.5 * boxes[index].width, boxes[index].y + 0.5 * boxes[index].height};
    boll.confidence = scores[index];
    bolls.push_back(boll);
  }
  return bolls;
}

}  // namespace perception
}  // namespace cotton_harvester
