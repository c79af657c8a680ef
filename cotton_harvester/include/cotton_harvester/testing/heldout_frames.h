#pragma once

#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "cotton_harvester/perception/camera_model.h"
#include "cotton_harvester/testing/detection_scoring.h"
#include "cotton_harvester/testing/synthetic_scene.h"

namespace cotton_harvester {
namespace perception {

/// A held-out frame of the simulated cotton row (cotton_harvester_sim's boll_dataset_export --full): colour, the
/// organised cloud rebuilt from its depth, and the truth as a SceneLayout for scoreFrame.
struct HeldoutFrame {
  std::string name;
  cv::Mat bgr;    ///< 1280x720 colour
  cv::Mat cloud;  ///< CV_32FC3, camera frame [m], NaN where the camera gave no depth
  SceneLayout truth;
  bool sunny = false;
};

/// How far in front of its centre a datasheet boll's visible top lies, in boll radii: the datasheet world's boll
/// (thorvald_sim cotton_world) is a core sphere of 0.6 R with five lobes of 0.55 R (0.5 R high) on a ring of 0.45 R,
/// as wide as a sphere of R seen from above but only about 0.6 R high (a half-open boll about 0.4 R).
constexpr double kDatasheetBollTopFraction = 0.6;

/// The frame names of an export folder that have a colour image, depth and truth, sorted.
std::vector<std::string> listHeldoutFrames(const std::string& dir);

/// Reads one frame; the cloud is rebuilt through `intrinsics` (x = (u - cx) z / fx). A boll's truth: its centre,
/// the visible surface point on the ray through it (centre - radius * centre / |centre|), its pixel, radius and
/// visible share. top_fraction: the surface point lies top_fraction radii in front of the centre (1: a sphere).
/// Returns false (error says why) when a file is missing or unreadable.
bool loadHeldoutFrame(const std::string& dir, const std::string& name, const CameraIntrinsics& intrinsics,
                      HeldoutFrame* frame, std::string* error, double top_fraction = kDatasheetBollTopFraction);

/// Parses a truth file's lines (see boll_dataset_export) into `frame`'s truth and day (a boll's radius in metres from
/// its pixel radius and depth). False on a malformed line.
bool parseHeldoutTruth(const std::string& text, const CameraIntrinsics& intrinsics, HeldoutFrame* frame,
                       double top_fraction = kDatasheetBollTopFraction);

/// A stricter score: a matched detection further than max_error_m in 3D from the boll's surface point (with
/// of_centre: its centre estimate further than that from the boll's centre) counts as a false positive and its boll
/// as missed.
FrameScore withinDistance(FrameScore score, double max_error_m, bool of_centre = false);

}  // namespace perception
}  // namespace cotton_harvester
