#pragma once

#include <vector>

#include <Eigen/Core>

namespace greenhouse_rail_nav {

/// A straight line fitted to 2D points by least squares (orthogonal regression: it minimises the
/// squared distances perpendicular to the line, so it works for any orientation, unlike y-on-x regression).
struct LineFit2D {
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();    ///< [m] a point on the line
  Eigen::Vector2d direction = Eigen::Vector2d::UnitX();  ///< unit vector along the line
  double s_min = 0.0;         ///< [m] smallest projection of a point on the direction, relative to the centroid
  double s_max = 0.0;         ///< [m] largest projection
  double rms_residual = 0.0;  ///< [m] RMS perpendicular distance of the points to the line
  /// Goodness of fit in [0, 1]: 1 - lambda_min / lambda_max of the scatter matrix. It plays the role of
  /// the paper's correlation coefficient r but, unlike Pearson's r, does not vanish for a line parallel
  /// to an axis (the rails run along base_link's x axis).
  double linearity = 0.0;
  std::size_t count = 0;  ///< number of points used

  double length() const { return s_max - s_min; }
  /// Signed perpendicular distance of p from the line [m] (positive to the left of the direction).
  double signedDistance(const Eigen::Vector2d& p) const {
    const Eigen::Vector2d d = p - centroid;
    return direction.x() * d.y() - direction.y() * d.x();
  }
  /// Projection of p on the line, relative to the centroid [m].
  double along(const Eigen::Vector2d& p) const { return direction.dot(p - centroid); }
  /// Flips the direction (and the extents with it).
  void flip();
};

/// Fits a line to the points; needs at least 2 distinct points (else count = points.size() and
/// linearity = 0).
LineFit2D fitLine(const std::vector<Eigen::Vector2d>& points);

/// Angle between two lines given by unit directions, in [0, pi/2] (a line and its reverse are the same line).
double angleBetweenLines(const Eigen::Vector2d& a, const Eigen::Vector2d& b);
/// Whether two fitted lines are perpendicular within `tolerance` [rad].
bool perpendicular(const LineFit2D& a, const LineFit2D& b, double tolerance);

}  // namespace greenhouse_rail_nav
