#include "cotton_harvester/testing/heldout_frames.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include <opencv2/imgcodecs.hpp>

namespace cotton_harvester {
namespace perception {

namespace fs = std::filesystem;

std::vector<std::string> listHeldoutFrames(const std::string& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(fs::path(dir) / "images", ec)) {
    const std::string name = entry.path().stem().string();
    if (fs::exists(fs::path(dir) / "depth" / (name + ".png")) && fs::exists(fs::path(dir) / "truth" / (name + ".txt")))
      names.push_back(name);
  }
  std::sort(names.begin(), names.end());
  return names;
}

bool parseHeldoutTruth(const std::string& text, const CameraIntrinsics& k, HeldoutFrame* frame, double top_fraction) {
  std::istringstream lines(text);
  std::string line;
  frame->truth = SceneLayout{};
  while (std::getline(lines, line)) {
    std::istringstream in(line);
    std::string kind;
    if (!(in >> kind)) continue;
    if (kind == "day") {
      std::string day;
      if (!(in >> day)) return false;
      frame->sunny = day == "sunny";
    } else if (kind == "boll") {
      TrueBoll b;
      if (!(in >> b.pixel.x >> b.pixel.y >> b.radius_px >> b.visible_fraction >> b.centre.x >> b.centre.y >>
            b.centre.z))
        return false;
      b.radius_m = b.radius_px * b.centre.z / k.fx;
      const double norm = std::sqrt(b.centre.dot(b.centre));
      b.surface = b.centre - b.centre * (top_fraction * b.radius_m / norm);
      frame->truth.bolls.push_back(b);
    } else if (kind == "end_effector") {
      TrueEndEffector e;
      if (!(in >> e.pixel.x >> e.pixel.y >> e.visible_fraction >> e.top_centre.x >> e.top_centre.y >> e.top_centre.z))
        return false;
      frame->truth.end_effector = e;
    } else {
      return false;
    }
  }
  return true;
}

bool loadHeldoutFrame(const std::string& dir, const std::string& name, const CameraIntrinsics& k, HeldoutFrame* frame,
                      std::string* error, double top_fraction) {
  const fs::path root(dir);
  frame->name = name;
  frame->bgr = cv::imread((root / "images" / (name + ".png")).string(), cv::IMREAD_COLOR);
  const cv::Mat depth = cv::imread((root / "depth" / (name + ".png")).string(), cv::IMREAD_ANYDEPTH);
  std::ifstream truth_file(root / "truth" / (name + ".txt"));
  std::stringstream text;
  text << truth_file.rdbuf();
  if (frame->bgr.empty() || depth.empty() || depth.type() != CV_16U || !truth_file.good() ||
      depth.size() != frame->bgr.size()) {
    *error = "frame '" + name + "' in '" + dir + "': colour, 16-bit depth or truth missing or of other sizes";
    return false;
  }
  if (!parseHeldoutTruth(text.str(), k, frame, top_fraction)) {
    *error = "frame '" + name + "': malformed truth";
    return false;
  }
  const float nan = std::numeric_limits<float>::quiet_NaN();
  frame->cloud = cv::Mat(depth.size(), CV_32FC3, cv::Scalar::all(nan));
  for (int v = 0; v < depth.rows; ++v)
    for (int u = 0; u < depth.cols; ++u) {
      const uint16_t mm = depth.at<uint16_t>(v, u);
      if (mm == 0) continue;
      const float z = mm * 1e-3f;
      frame->cloud.at<cv::Vec3f>(v, u) = {static_cast<float>((u - k.cx) * z / k.fx),
                                          static_cast<float>((v - k.cy) * z / k.fy), z};
    }
  return true;
}

FrameScore withinDistance(FrameScore score, double max_error_m, bool of_centre) {
  std::vector<double> errors, centre_errors;
  std::vector<size_t> matched, detections;
  for (size_t i = 0; i < score.errors_3d_m.size(); ++i) {
    const double centre_error = i < score.centre_errors_3d_m.size() ? score.centre_errors_3d_m[i] : 0.0;
    if ((of_centre ? centre_error : score.errors_3d_m[i]) <= max_error_m) {
      errors.push_back(score.errors_3d_m[i]);
      centre_errors.push_back(centre_error);
      matched.push_back(score.matched_bolls[i]);
      if (i < score.matched_detections.size()) detections.push_back(score.matched_detections[i]);
      continue;
    }
    --score.true_positives;
    ++score.false_positives;
    ++score.false_negatives;
    score.missed_bolls.push_back(score.matched_bolls[i]);
  }
  score.errors_3d_m = errors;
  score.centre_errors_3d_m = centre_errors;
  score.matched_bolls = matched;
  score.matched_detections = detections;
  return score;
}

}  // namespace perception
}  // namespace cotton_harvester
