// The cotton camera's frame in each realism profile side by side (harvest_bench --realism-frames).
#include <cmath>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "cotton_harvester_sim/harvest_run.h"

namespace cotton_harvester {
namespace sim {

namespace {

/// Depth [m] of the cloud as colours: near red to far blue over 0.8..2.4 m, black where there is none.
cv::Mat depthColours(const cv::Mat& cloud) {
  cv::Mat grey(cloud.rows, cloud.cols, CV_8UC1), holes(cloud.rows, cloud.cols, CV_8UC1);
  for (int v = 0; v < cloud.rows; ++v)
    for (int u = 0; u < cloud.cols; ++u) {
      const float z = cloud.at<cv::Vec3f>(v, u)[2];
      holes.at<uint8_t>(v, u) = std::isfinite(z) ? 0 : 255;
      const double t = std::isfinite(z) ? std::clamp((z - 0.8) / 1.6, 0.0, 1.0) : 0.0;
      grey.at<uint8_t>(v, u) = static_cast<uint8_t>(std::lround(255.0 * (1.0 - t)));
    }
  cv::Mat out;
  cv::applyColorMap(grey, out, cv::COLORMAP_JET);
  out.setTo(cv::Scalar(0, 0, 0), holes);
  return out;
}

void label(cv::Mat* img, const std::string& text) {
  cv::putText(*img, text, cv::Point(16, 44), cv::FONT_HERSHEY_SIMPLEX, 1.3, cv::Scalar(0, 0, 0), 6);
  cv::putText(*img, text, cv::Point(16, 44), cv::FONT_HERSHEY_SIMPLEX, 1.3, cv::Scalar(255, 255, 255), 2);
}

}  // namespace

bool writeRealismFrames(const RoverSimParams& base, const std::string& path) {
  cv::Mat columns[2];
  const thorvald_sim::Realism profiles[2] = {thorvald_sim::Realism::kIdeal, thorvald_sim::Realism::kDatasheet};
  for (int i = 0; i < 2; ++i) {
    RoverSimParams p = base;
    p.realism = profiles[i];
    p.start_x_m = base.row.first_plant_x_m + 0.45 - p.geometry.camera_ahead_m;  // the camera over the plants
    RoverSim s(p);
    cv::Mat bgr, cloud;
    s.renderCamera(&bgr, &cloud);
    cv::Mat depth = depthColours(cloud);
    const std::string name = thorvald_sim::realismName(profiles[i]);
    std::string day;
    if (profiles[i] == thorvald_sim::Realism::kDatasheet) day = s.daylight().sunny ? ", sunny" : ", overcast";
    label(&bgr, name + ": colour" + day);
    label(&depth, name + ": depth (0.8 m red .. 2.4 m blue, black none)");
    cv::vconcat(bgr, depth, columns[i]);
  }
  cv::Mat both, small;
  cv::hconcat(columns[0], columns[1], both);
  cv::resize(both, small, cv::Size(), 0.5, 0.5, cv::INTER_AREA);
  return cv::imwrite(path, small);
}

}  // namespace sim
}  // namespace cotton_harvester
