#include "cotton_harvester/perception/debug_overlay.h"

#include <cstdio>

#include <opencv2/imgproc.hpp>

namespace cotton_harvester {
namespace perception {
namespace {

const cv::Scalar kPink(180, 105, 255);  // BGR
const cv::Scalar kBlue(255, 60, 0);
const cv::Scalar kGreen(0, 220, 0);
const cv::Scalar kGrey(160, 160, 160);

}  // namespace

cv::Mat drawDebugOverlay(const cv::Mat& bgr, const FrameResult& result) {
  cv::Mat canvas;
  if (bgr.empty()) return canvas;
  if (bgr.type() == CV_8UC3) {
    canvas = bgr.clone();
  } else if (bgr.type() == CV_8UC1) {
    cv::cvtColor(bgr, canvas, cv::COLOR_GRAY2BGR);
  } else {
    return canvas;
  }

  for (size_t i = 0; i < result.bolls.size(); ++i) {
    const LocatedBoll& boll = result.bolls[i];
    const bool nearest = static_cast<int>(i) == result.nearest_reachable;
    const cv::Scalar colour = nearest ? kBlue : kPink;
    const cv::Rect box(boll.detection.box);
    cv::rectangle(canvas, box, colour, nearest ? 3 : (boll.reachable ? 2 : 1));
    char label[32];
    std::snprintf(label, sizeof(label), "%.2fm", boll.range_m);
    cv::putText(canvas, label, {box.x, std::max(10, box.y - 4)}, cv::FONT_HERSHEY_SIMPLEX, 0.4, colour, 1);
  }
  if (!result.boll_exclusion.empty()) {
    std::vector<std::vector<cv::Point>> contours;
    cv::findContours(result.boll_exclusion.clone(), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
    cv::drawContours(canvas, contours, -1, kGrey, 1);
  }
  if (!result.end_effector_mask.empty()) {
    std::vector<std::vector<cv::Point>> contours;
    cv::findContours(result.end_effector_mask.clone(), contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
    cv::drawContours(canvas, contours, -1, kGreen, 2);
  }
  if (result.end_effector_image) {
    const cv::Point p(result.end_effector_image->pixel);
    cv::drawMarker(canvas, p, kGreen, cv::MARKER_CROSS, 20, 2);
  }
  return canvas;
}

}  // namespace perception
}  // namespace cotton_harvester
