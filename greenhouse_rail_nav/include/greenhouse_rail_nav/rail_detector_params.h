#pragma once

#include <string>

namespace greenhouse_rail_nav {

/// Settings of the rail fitting (paper Algorithm 1). base_link is taken to lie on the floor under the
/// middle of the drive wheels, so the rails' height band is measured from the floor.
struct RailDetectorParams {
  double rail_gauge_m = 0.55;       ///< centre distance of the two pipes [m]
  double gauge_tolerance_m = 0.05;  ///< the partner rail is searched at gauge +- this [m]
  /// Each depth point is moved along its ray to the median range of this many x this many pixels around it
  /// before the search (medianAlongRays; odd; 0 or 1: off): the active-stereo range noise (about 2 % at 2 m)
  /// would otherwise fill the rails' height band with floor points.
  int depth_median_px = 0;
  /// When the depth points show no rails, the pixels without depth are laid on the plane this high above the floor
  /// and searched the same way (holesOnPlane: shiny pipes reflect an active-stereo pattern away) [m]; 0: off.
  double pipe_hole_height_m = 0.0;
  double crop_z_min_m = 0.015;  ///< rails' height band in base_link [m]
  double crop_z_max_m = 0.10;
  double crop_x_min_m = 0.0;  ///< region ahead of the robot that is searched [m]
  double crop_x_max_m = 3.0;
  double crop_y_max_m = 1.5;          ///< |y| limit [m]
  double voxel_size_m = 0.02;         ///< the cropped points are thinned to one per voxel (0: off) [m]
  double cluster_tolerance_m = 0.03;  ///< Euclidean clustering distance [m]
  int min_cluster_points = 30;        ///< smaller clusters are dropped (after thinning)
  int max_cluster_points = 200000;
  double min_line_length_m = 0.3;        ///< a rail cluster is at least this long [m]
  double min_linearity = 0.97;           ///< and at least this straight (fit linearity, the paper's r)
  double rail_trim_m = 0.03;             ///< a rail's line is refitted on its points this close to it [m]
  double height_tolerance_m = 0.01;      ///< the two rails' median heights agree within this [m]
  double min_partner_coverage = 0.7;     ///< a partner taken from loose points must fill this share of 5 cm bins
  double parallel_tolerance_rad = 0.08;  ///< the partner's direction may differ by this [rad]
  double max_abs_yaw_rad = 0.8;          ///< rails are only searched within this heading of the robot [rad]
  double max_lateral_offset_m = 0.45;    ///< the rail set's centre line must pass this close to base_link [m]
  double ransac_distance_m = 0.015;      ///< baseline: RANSAC inlier distance [m]
  int ransac_max_lines = 4;              ///< baseline: lines taken by sequential RANSAC
  int ransac_iterations = 500;           ///< baseline: RANSAC iterations per line
  /// Lower bounds of the reported standard deviations (the paper's RMS errors, Table I) [m, m, rad].
  double sigma_x_m = 0.11, sigma_y_m = 0.02, sigma_yaw_rad = 0.014;
  /// The rails' start counts as seen only when the point this far in front of it lies inside the image and
  /// the floor there is seen where it lies inside the image [m]. The start is found to within about one
  /// voxel, so this is a voxel and a centimetre.
  double start_view_margin_m = 0.03;
  /// Standard deviation of x reported when the rails' start is out of view [m].
  double unobserved_sigma_x_m = 0.5;
  /// Pipe radius [m]: the camera sees the side of a pipe that faces it, whose points lie nearer the camera
  /// than the pipe's axis. Each rail's axis is found by fitting a circle of this radius to the rail's
  /// points across the rail (lateral offset, height), before thinning and trimming, so neither changes
  /// which part of the surface counts. 0: no correction (the line through the visible points).
  double pipe_radius_m = 0.0255;
  /// The rails' start counts as in view only when the point start_view_margin_m before it projects at
  /// least this far inside the image border (projection recovered from the organised cloud) [px].
  double image_margin_px = 2.0;

  /// Empty if valid, else which key is wrong and what it must be.
  std::string validate() const;
};

}  // namespace greenhouse_rail_nav
