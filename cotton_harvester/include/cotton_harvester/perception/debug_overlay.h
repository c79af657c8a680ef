#pragma once

#include <opencv2/core.hpp>

#include "cotton_harvester/perception/perception_pipeline.h"

namespace cotton_harvester {
namespace perception {

/// Draws a frame's result over a copy of its image as in the paper's Figure 8: pink boxes around the bolls
/// (thin when unreachable), the nearest reachable boll in blue, the end-effector's region outline and point in
/// green, the region not searched for bolls (end-effector and arm band) outlined in grey, and the range of each
/// boll [m] next to its box.
cv::Mat drawDebugOverlay(const cv::Mat& bgr, const FrameResult& result);

}  // namespace perception
}  // namespace cotton_harvester
