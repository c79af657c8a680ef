#pragma once

// The `datasheet` depth models of stereo cameras, on images of depth along the optical axis (row-major, row 0 at
// the top, NaN where there is no depth). Active stereo: the RealSense ZR300 / D400 class of the greenhouse robot.
// Passive stereo: the ZED of the cotton rover. ROS-free and deterministic given the random engine.

#include <Eigen/Core>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

namespace thorvald_sim {

/// Active (projected-pattern) stereo errors; figures and sources in the README.
struct ActiveStereoModel {
  double noise_coeff = 0.01;          ///< depth std dev = noise_coeff * z^2 [1/m]: 1 % at 1 m, 2 % at 2 m
  double baseline_m = 0.05;           ///< left-right imager baseline [m]: the invalid band is baseline*fx/z wide
  double range_min_m = 0.11;          ///< no depth nearer than this [m] (and the camera's range_min)
  double dropout = 0.005;             ///< probability that a valid pixel has no depth
  double edge_jump = 0.05;            ///< a neighbour this much farther or nearer (fraction of z) makes a depth edge
  double flying_probability = 0.5;    ///< chance that a pixel on a depth edge gets a depth between the surfaces
  std::string shiny_prefix = "rail";  ///< round geoms whose name starts with this are shiny steel ("": none)
  /// Half width [rad] of the glint band of a shiny round geom: no depth where the surface normal lies within this
  /// angle of the plane through the geom's axis and the camera (DepthTruth::glint_rad). A visible pipe loses the
  /// share sin(shiny_band) of its pixels (orthographic view of a cylinder; README).
  double shiny_band_rad = 0.35;
};

/// The true view: depth along the optical axis [m] (NaN: nothing seen) and, where the pixel sees a shiny round
/// surface, its angle from the glint line [rad] (NaN elsewhere): on a capsule or cylinder the angle between the
/// surface normal and the plane through the axis and the camera (the line where the normal lies in that plane is the
/// glossy pipe's mirror line, see glintAngle); on a sphere or ellipsoid the angle between the normal and the way
/// back to the camera.
struct DepthTruth {
  int width = 0, height = 0;
  std::vector<float> z_m;
  std::vector<float> glint_rad;
};

/// The angle [rad] between the unit surface normal `n` at `point` and the plane through the axis line (through
/// `centre`, unit direction `axis`) and the `camera` position: asin |n . q|, q the plane's unit normal. With no axis
/// (`axis` zero) or the camera on the axis line: the angle between n and the way back to the camera.
double glintAngle(const Eigen::Vector3d& n, const Eigen::Vector3d& point, const Eigen::Vector3d& centre,
                  const Eigen::Vector3d& axis, const Eigen::Vector3d& camera);

/// What the active-stereo camera reports for `truth` (z [m], NaN: none): no depth below the minimum range, in the
/// left invalid band (u < baseline * fx / z, the columns the right imager does not share), in the glint band of shiny
/// surfaces (glint_rad < shiny_band_rad), on dropouts; pixels on depth edges become flying pixels with
/// flying_probability (a depth uniform between the pixel's and its farthest-off 4-neighbour's); then noise noise_coeff
/// * z^2.
std::vector<float> applyActiveStereo(const DepthTruth& truth, double fx_px, const ActiveStereoModel& model,
                                     std::mt19937& rng);

/// Passive stereo matching errors (ZED); figures and sources in the README.
struct PassiveStereoModel {
  double baseline_m = 0.12;          ///< [m]
  double disparity_sigma_px = 0.25;  ///< matching noise std dev [px]
  int texture_window_px = 7;         ///< side of the window of the local intensity variance (odd) [px]
  double min_texture_sigma = 2.0;    ///< no match where the window's grey-level std dev is below this
  int saturation_level = 250;        ///< no match where a colour channel is at or above this
};

/// Buffers passiveStereoDepth reuses from frame to frame (per camera; contents are scratch).
struct PassiveStereoScratch {
  std::vector<char> seen, ok;
  std::vector<int64_t> col_sum, col_sq;
};

/// What stereo matching gives for the true depth `z_m` (row-major width x height, NaN: none) and the left colour
/// image `rgb` (rgb8, same size): no depth where the left pixel is hidden from the right camera (left-right
/// occlusion, or outside the right image), on textureless or saturated pixels; elsewhere z plus noise
/// sigma_z = z^2 * disparity_sigma / (fx * baseline).
std::vector<float> passiveStereoDepth(const std::vector<float>& z_m, const std::vector<uint8_t>& rgb, int width,
                                      int height, double fx_px, const PassiveStereoModel& model, std::mt19937& rng);
/// The same into `out`, with the buffers of `scratch` (no allocation once they have grown to the image).
void passiveStereoDepth(const std::vector<float>& z_m, const std::vector<uint8_t>& rgb, int width, int height,
                        double fx_px, const PassiveStereoModel& model, std::mt19937& rng, std::vector<float>* out,
                        PassiveStereoScratch* scratch);

}  // namespace thorvald_sim
