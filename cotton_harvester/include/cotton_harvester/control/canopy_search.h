#pragma once

#include <optional>
#include <string>

#include "cotton_harvester/control/leaf_clearance.h"

namespace cotton_harvester {
namespace control {

/// Looking under the leaves: in undefoliated cotton a leaf lying just above a boll hides it from a camera looking
/// down from every place on the row. Before the rover passes on, the arm sweeps the foliage in its own strip of the
/// row aside, one layer at a time from the top: it goes down beside the layer, moves sideways through it (the
/// housing pushes the leaves ahead of it), goes up, and a new frame shows what lay underneath. A layer is the
/// shallowest group of cloud points in the strip, deeper than the last sweep, that covers at least
/// `min_cover_fraction` of a boll's disc as the camera sees it at that depth (so it scales with the camera's
/// resolution and height). Lengths [m], camera frame (x across the row along the arm's extension, y along the row,
/// z down from the camera).
struct CanopySearchParams {
  double strip_half_m = 0.08;       ///< the strip: within this of the end-effector's y
  double boll_radius_m = 0.035;     ///< the smallest boll worth looking for
  double min_cover_fraction = 0.5;  ///< a layer covers at least this share of that boll's disc
  double layer_m = 0.04;            ///< a layer's points lie within this below its shallowest one
  double above_layer_m = 0.01;      ///< the housing's top face goes this far above the layer's top
  double housing_height_m = 0.08;   ///< the end-effector housing's height
  double effector_half_m = 0.05;    ///< its half side
  double push_m = 0.15;             ///< the sweep ends this far past the layer's far edge (leaves bend that far)
  int max_passes = 3;               ///< sweeps at one place of the row at most
  std::string check() const;        ///< empty when sound
};

/// A layer of foliage to sweep: the housing's depth (top face) and the sideways span of its points.
struct CanopyLayer {
  double sweep_depth_m = 0.0;  ///< where the housing's top face goes
  double top_m = 0.0;          ///< the layer's shallowest point
  double x_min_m = 0.0, x_max_m = 0.0;
  int points = 0;  ///< points of the layer (whole-resolution count)
};

/// The shallowest layer in `cloud` (every second row and column) deeper than `below_depth_m`, within the strip
/// around `strip_y_m`, with points between `x_min_m` and `x_max_m` and no deeper than `max_depth_m` (the arm's
/// lowest position plus the housing's height), or nullopt when there is none. `fx` is the camera's focal length in
/// pixels.
std::optional<CanopyLayer> nextCanopyLayer(const CloudView& cloud, double fx, double strip_y_m, double x_min_m,
                                           double x_max_m, double below_depth_m, double max_depth_m,
                                           const CanopySearchParams& params);

/// The arm as the stack knows it from its calibration (the manipulator's travel), camera frame [m]. The defaults are
/// the simulated rover's build (the harvest_mujoco_nodes.yaml values); the paper's rover has 0.60 m of horizontal
/// travel and 0.30-1.17 m of vertical (config/harvest.yaml).
struct ArmWorkspace {
  double extension_zero_x_m = -0.55;                     ///< camera x of the housing's centre at extension 0
  double extension_min_m = 0.0, extension_max_m = 0.70;  ///< horizontal travel: targets are clamped into it
  double min_depth_m = 0.30, max_depth_m = 1.93;         ///< housing's top face, highest and lowest
  /// Rest: where the horizontal axis waits between picks and while the rover drives ...
  double rest_extension_m = 0.35;
  /// ... and the depth above the plants the housing goes up to (when deeper) as the rover starts a move and before
  /// looking under the leaves; 0: none (the arm keeps its depth while driving, and no search is possible).
  double rest_depth_m = 1.20;
  double strip_y_m = 0.0;  ///< camera y of the arm's plane (the housing's centre)
};

/// One sweep through a layer: the housing goes to `from_extension_m` above the plants, down to `depth_m`, sideways
/// to `to_extension_m`, and up. Layers are looked for only where the housing reaches, so every sweep spans at least
/// the housing's side and push_m.
struct CanopySweep {
  double from_extension_m = 0.0, to_extension_m = 0.0, depth_m = 0.0;
};

/// The sweeps at one place of the row, layer after layer from the top: each next() looks below what the last
/// sweep passed through.
class CanopySearch {
 public:
  CanopySearch(const ArmWorkspace& arm, const CanopySearchParams& params);
  /// The next layer's sweep in `cloud` (focal length `fx` [px]), or nullopt when no layer is left.
  std::optional<CanopySweep> next(const CloudView& cloud, double fx);

 private:
  ArmWorkspace arm_;
  CanopySearchParams params_;
  double below_m_;
};

/// The focal length [px] of the camera an organised cloud came from: the median over rows of the columns between
/// two points divided by the difference of their x / z (0 when the cloud has too few points to tell).
double focalFromCloud(const CloudView& cloud);

}  // namespace control
}  // namespace cotton_harvester
