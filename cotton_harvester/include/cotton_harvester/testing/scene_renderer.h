#pragma once

#include <cstdint>

#include <opencv2/core.hpp>

#include "cotton_harvester/testing/synthetic_scene.h"

namespace cotton_harvester {
namespace perception {

/// One synthetic camera frame with its ground truth.
struct SyntheticFrame {
  cv::Mat bgr;         ///< CV_8UC3 colour image
  cv::Mat cloud;       ///< CV_32FC3 organised cloud, camera frame [m], NaN where the stereo matcher has no depth
  SceneLayout layout;  ///< the scene and its truth (bolls' visible fractions filled in)
};

/// Renders a layout by ray casting each pixel against the scene's shapes (ground plane, horizontal leaves and
/// bars, spherical bolls): colour with the lighting's shading, shadows and noise; the cloud with stereo-like
/// depth noise (sigma = k z^2 along the ray), single-pixel holes, hole patches and an invalid left border.
SyntheticFrame renderScene(const SceneLayout& layout, const SceneParams& params, std::uint32_t seed);

/// generateLayout + renderScene with the same seed.
SyntheticFrame makeSyntheticFrame(const SceneParams& params, std::uint32_t seed);

}  // namespace perception
}  // namespace cotton_harvester
