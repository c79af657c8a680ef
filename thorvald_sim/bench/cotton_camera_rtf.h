#pragma once

// rtf_bench's cotton camera: the rover over the cotton row with its ZED (cotton_camera_rtf.cpp).

#include <random>

#include "rtf_bench_run.h"
#include "thorvald_sim/camera_renderer.h"

namespace rtf_bench {

/// The ZED as the rover carries it: 1280 x 720 at 15 Hz, the cotton paper's intrinsics, 2.2 m above the ground
/// looking down.
struct CottonCameraFigures {
  static constexpr int kWidth = 1280, kHeight = 720;
  static constexpr double kRateHz = 15.0;
  Rate ideal;      ///< ideal row, colour + depth image (ray-cast noise model) + IMU
  Rate datasheet;  ///< datasheet row, colour shaded by daylight + passive-stereo depth + IMU
  long ideal_frames = 0, datasheet_frames = 0;
  double boll_pixels = 0;  ///< white pixels per ideal frame
  /// Datasheet frames, CPU ms each: render, flat colour, sun's shadow map, daylight shading, passive stereo.
  double ds_render_ms = 0, ds_colour_ms = 0, ds_shadow_ms = 0, ds_shade_ms = 0, ds_stereo_ms = 0;
  long shadow_renders = 0;      ///< shadow maps rendered (the rest reused)
  double ds_rest_ms_per_s = 0;  ///< the datasheet run's CPU besides the camera (physics, IMU) per simulated second [ms]
  thorvald_sim::CameraRenderer::StageTimes ds_render_stages;  ///< the datasheet camera's render, summed [s]
  /// One ideal frame alone: CPU and wall ms; render, depth image, colour image; the render's parts.
  double frame_ms = 0, frame_wall_ms = 0, stage_ms[3] = {0, 0, 0};
  thorvald_sim::CameraRenderer::StageTimes render_stages;  ///< per frame [s]
};

/// Drives the rover `seconds` along the ideal row and again along the datasheet row with the camera and IMU, then
/// times `frames` ideal frames alone. Prints its scene lines as each is done.
CottonCameraFigures cottonCamera(double seconds, int frames, int image_threads, std::mt19937& rng);

/// The frame-alone lines (after the greenhouse's).
void printCottonFrame(const CottonCameraFigures& f, int frames);

}  // namespace rtf_bench
